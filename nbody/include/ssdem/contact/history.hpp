/// @file history.hpp
/// The one container of per-contact history (structure of arrays): a flag `active` per row and
/// one column per history field of the enabled parts (table.hpp: n_old, then the parts' fields
/// in table order; columns of parts that are off are empty and cost nothing). The same container
/// serves the sphere-sphere pair list (row = pair), the wall contacts (row = sphere * walls +
/// wall) and, through HistoryRecord, the checkpoints (one dataset per field, by its name).
/// A later per-pair time step (rung) is one more column of this container.
#pragma once
#include <cstdint>
#include <string_view>
#include <vector>

#include "ssdem/contact/table.hpp"

namespace ssdem {

/// One contact's history keyed by sphere ids (checkpoints). For a wall contact
/// id_b = kWallIdBase + wall index. v/q follow the column order of the table (kHistVecFields,
/// kHistScalFields); columns of parts that are off are zero.
struct HistoryRecord {
  std::uint64_t id_a = 0, id_b = 0;
  std::array<Vec3, kHistVec> v;
  std::array<double, kHistScal> q;
  HistoryRecord() {
    for (auto& x : v) x.setZero();
    q.fill(0.0);
  }
  /// Column by field name (std::out_of_range if the table has no such field).
  Vec3& vec(std::string_view name);
  const Vec3& vec(std::string_view name) const;
  double& scal(std::string_view name);
  double scal(std::string_view name) const;
};
// Records move between ranks as raw bytes (MPI exchanges, the collective checkpoint's sort):
// they must have no padding, whose bytes would be indeterminate.
static_assert(sizeof(HistoryRecord) == 2 * sizeof(std::uint64_t) + kHistVec * sizeof(Vec3) + kHistScal * sizeof(double),
              "HistoryRecord has padding");
inline constexpr std::uint64_t kWallIdBase = 0xFFFFFFFF00000000ull;

/// One row of a container as the kernel sees it.
struct HistRow {
  const HistCols* c;
  std::size_t row;
};

class ContactHistory {
 public:
  ContactHistory() = default;
  explicit ContactHistory(unsigned parts) { configure(parts); }
  ContactHistory(const ContactHistory& o)
      : active(o.active), parts_(o.parts_), von_(o.von_), qon_(o.qon_), v_(o.v_), q_(o.q_) {
    refresh();
  }
  ContactHistory& operator=(const ContactHistory& o) {
    parts_ = o.parts_;
    von_ = o.von_;
    qon_ = o.qon_;
    active = o.active;
    v_ = o.v_;
    q_ = o.q_;
    refresh();
    return *this;
  }
  /// Choose the columns for a set of parts (clears everything).
  void configure(unsigned parts);
  unsigned parts() const { return parts_; }
  bool any_columns() const;
  /// rows, all inactive and zero.
  void assign(std::size_t rows);
  std::size_t size() const { return active.size(); }
  void swap(ContactHistory& o);
  /// Copy row q of `from` (same configuration) into row `to`, which becomes active.
  void copy_row(std::size_t to, const ContactHistory& from, std::size_t q);
  /// Set row `to` from a record (active); `flip` negates the fields that flip with the pair order.
  void set_from(std::size_t to, const HistoryRecord& r, bool flip);
  /// Fill the columns of a record from row `row` (ids untouched).
  void get_into(std::size_t row, HistoryRecord& r) const;
  HistRow row(std::size_t r) const { return HistRow{&cols_, r}; }
  const HistCols& cols() const { return cols_; }
  /// Column k of the table (vector / scalar); empty if its part is off.
  std::vector<Vec3>& vec_col(int k) { return v_[k]; }
  std::vector<double>& scal_col(int k) { return q_[k]; }
  /// Bytes per row of the enabled columns (flag included).
  double bytes_per_row() const;

  std::vector<std::uint8_t> active;  ///< 1 if the contact existed at the previous evaluation

 private:
  void refresh();
  unsigned parts_ = 0;
  std::array<bool, kHistVec> von_{};
  std::array<bool, kHistScal> qon_{};
  std::array<std::vector<Vec3>, kHistVec> v_;
  std::array<std::vector<double>, kHistScal> q_;
  HistCols cols_;
};

}  // namespace ssdem
