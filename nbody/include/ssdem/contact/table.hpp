/// @file table.hpp
/// The table of contact parts. Everything else is generated from it at compile time: the
/// parameter struct (ContactParams derives from every part's Params), the coefficient struct
/// (ContactCoeffs), the history columns (n_old, then every part's fields in table order), the
/// set of valid part combinations and the dispatch from a run-time set of parts to the pair
/// kernel compiled for it (contact_law.hpp, contacts.cpp), and the registry (contact_params.cpp).
/// Adding a law: write its header (see part.hpp for what it declares) and add one row here.
/// Rows are evaluated in this order inside the kernel (normal phase, then tangent phase).
#pragma once
#include <array>
#include <cstddef>
#include <type_traits>
#include <utility>

#include "ssdem/contact/cohesion.hpp"
#include "ssdem/contact/damping.hpp"
#include "ssdem/contact/normal_hertz.hpp"
#include "ssdem/contact/normal_linear.hpp"
#include "ssdem/contact/part.hpp"
#include "ssdem/contact/rolling.hpp"
#include "ssdem/contact/tangential.hpp"
#include "ssdem/contact/twisting.hpp"

namespace ssdem {

template <class... P>
struct PartList {
  static constexpr std::size_t size = sizeof...(P);
};

// ---------------------------------------------------------------- the table
using ContactTable = PartList<LinearNormal,  // normal law (default of the normal slot)
                              HertzNormal,   // normal law (alternative)
                              Damping,
                              Tangential,
                              Rolling,
                              Twisting,
                              Cohesion>;
// ----------------------------------------------------------------------------

namespace contact_table {

/// Number of history fields of width w (3: vector, 1: scalar) that part Q declares.
template <class Q>
constexpr std::size_t count_width(int w) {
  std::size_t k = 0;
  for (const auto& f : Q::history) k += f.width == w ? 1 : 0;
  return k;
}

template <class T> struct Info;
template <class... P>
struct Info<PartList<P...>> {
  /// OR of the flags of the parts in the normal slot.
  static constexpr unsigned normal_mask = ((P::slot == PartSlot::normal ? P::flag : 0u) | ...);
  static constexpr unsigned all_flags = (P::flag | ...);
  static constexpr int nvec = 1 + ((static_cast<int>(count_width<P>(3))) + ...);
  static constexpr int nscal = ((static_cast<int>(count_width<P>(1))) + ...);
  /// Whether part Q is enabled in the set PARTS (a slot default: no other law of its slot is).
  template <class Q>
  static constexpr bool enabled(unsigned parts) {
    if constexpr (Q::flag == 0u)
      return (parts & normal_mask) == 0u;
    else
      return (parts & Q::flag) != 0u;
  }
  /// First vector/scalar history column of part Q (column 0 is n_old).
  template <class Q>
  static constexpr int vec_base() {
    int b = 1;
    bool found = false;
    ((found = found || std::is_same_v<P, Q>, b += found ? 0 : static_cast<int>(count_width<P>(3))), ...);
    return b;
  }
  template <class Q>
  static constexpr int scal_base() {
    int b = 0;
    bool found = false;
    ((found = found || std::is_same_v<P, Q>, b += found ? 0 : static_cast<int>(count_width<P>(1))), ...);
    return b;
  }
  /// A set of flags is valid if it names at most one law per slot and every part's requirements.
  static constexpr bool valid(unsigned parts) {
    if ((parts & ~all_flags) != 0u) return false;
    const unsigned nm = parts & normal_mask;
    if ((nm & (nm - 1u)) != 0u) return false;  // two normal laws
    bool ok = true;
    ((ok = ok && (!(P::flag != 0u && (parts & P::flag)) || (parts & P::requires_parts) == P::requires_parts)), ...);
    return ok;
  }
  static constexpr std::size_t count_valid() {
    std::size_t k = 0;
    for (unsigned m = 0; m <= all_flags; ++m) k += valid(m) ? 1 : 0;
    return k;
  }
  /// Every valid set, ascending: one kernel is compiled for each.
  static constexpr auto valid_sets() {
    std::array<unsigned, count_valid()> out{};
    std::size_t k = 0;
    for (unsigned m = 0; m <= all_flags; ++m)
      if (valid(m)) out[k++] = m;
    return out;
  }
  /// Whether any enabled part keeps history (then n_old is kept too).
  static constexpr bool has_history(unsigned parts) {
    return ((enabled<P>(parts) && P::history.size() > 0) || ...);
  }
  /// Metadata of every history column, and whether it exists for a set of parts.
  static constexpr auto vec_fields() {
    std::array<HistoryField, nvec> out{};
    out[0] = kNormalOldField;
    int k = 1;
    ((fill_fields<P>(out, k, 3)), ...);
    return out;
  }
  static constexpr auto scal_fields() {
    std::array<HistoryField, nscal> out{};
    int k = 0;
    ((fill_fields<P>(out, k, 1)), ...);
    return out;
  }
  static constexpr std::array<unsigned, nvec> vec_owner() {
    std::array<unsigned, nvec> out{};
    int k = 1;
    ((fill_owner<P>(out, k, 3)), ...);
    return out;
  }
  static constexpr std::array<unsigned, nscal> scal_owner() {
    std::array<unsigned, nscal> out{};
    int k = 0;
    ((fill_owner<P>(out, k, 1)), ...);
    return out;
  }
  template <class Q, class A>
  static constexpr void fill_fields(A& out, int& k, int w) {
    for (const auto& f : Q::history)
      if (f.width == w) out[k++] = f;
  }
  // owner: index of the part in the table + 1 (0 = the kernel's n_old)
  template <class Q, class A>
  static constexpr void fill_owner(A& out, int& k, int w) {
    constexpr unsigned idx = index_of<Q>();
    for (const auto& f : Q::history)
      if (f.width == w) out[k++] = idx + 1u;
  }
  template <class Q>
  static constexpr unsigned index_of() {
    unsigned i = 0;
    bool found = false;
    ((found = found || std::is_same_v<P, Q>, i += found ? 0u : 1u), ...);
    return i;
  }
  /// Whether the part at table index i is enabled in `parts`.
  static constexpr bool enabled_at(unsigned i, unsigned parts) {
    unsigned k = 0;
    bool r = false;
    ((r = r || (k++ == i && enabled<P>(parts))), ...);
    return r;
  }
  /// Parameters and coefficients composed from the parts.
  struct Params : P::Params... {};
  struct Coeffs : P::Coeffs... {
    template <class Q>
    explicit Coeffs(const Q& q) : P::Coeffs(q)... {}
  };
  /// f(part tag) for each part, in table order.
  template <class F>
  static void for_each(F&& f) {
    (f(static_cast<P*>(nullptr)), ...);
  }
};

}  // namespace contact_table

using TableInfo = contact_table::Info<ContactTable>;
inline constexpr int kHistVec = TableInfo::nvec;
inline constexpr int kHistScal = TableInfo::nscal;
inline constexpr auto kHistVecFields = TableInfo::vec_fields();
inline constexpr auto kHistScalFields = TableInfo::scal_fields();
using HistCols = HistoryCols<kHistVec, kHistScal>;
/// Every valid set of parts (one compiled kernel each).
inline constexpr auto kValidPartSets = TableInfo::valid_sets();

/// Whether history column k (vector or scalar) exists for a set of parts.
constexpr bool vec_column_enabled(int k, unsigned parts) {
  if (k == 0) return TableInfo::has_history(parts);
  return TableInfo::enabled_at(TableInfo::vec_owner()[k] - 1u, parts);
}
constexpr bool scal_column_enabled(int k, unsigned parts) {
  return TableInfo::enabled_at(TableInfo::scal_owner()[k] - 1u, parts);
}

namespace contact_table {
template <class F, std::size_t... I>
decltype(auto) dispatch_impl(unsigned parts, F&& f, std::index_sequence<I...>) {
  using R = decltype(f(std::integral_constant<unsigned, kValidPartSets[0]>{}));
  R r{};
  const bool hit = ((parts == kValidPartSets[I] ? (r = f(std::integral_constant<unsigned, kValidPartSets[I]>{}), true) : false) || ...);
  (void)hit;
  return r;
}
}  // namespace contact_table

/// Call f(std::integral_constant<unsigned, parts>) for the compiled kernel of a valid set.
template <class F>
decltype(auto) dispatch_parts(unsigned parts, F&& f) {
  return contact_table::dispatch_impl(parts, std::forward<F>(f),
                                      std::make_index_sequence<kValidPartSets.size()>{});
}

}  // namespace ssdem
