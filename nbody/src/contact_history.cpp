/// @file contact_history.cpp
/// The history container and records (contact/history.hpp).
#include "ssdem/contact/history.hpp"

#include <stdexcept>
#include <string>

namespace ssdem {
namespace {
template <class A>
int find_field(const A& fields, std::string_view name) {
  for (std::size_t k = 0; k < fields.size(); ++k)
    if (name == fields[k].name) return static_cast<int>(k);
  throw std::out_of_range("no contact history field '" + std::string(name) + "'");
}
}  // namespace

Vec3& HistoryRecord::vec(std::string_view name) { return v[find_field(kHistVecFields, name)]; }
const Vec3& HistoryRecord::vec(std::string_view name) const { return v[find_field(kHistVecFields, name)]; }
double& HistoryRecord::scal(std::string_view name) { return q[find_field(kHistScalFields, name)]; }
double HistoryRecord::scal(std::string_view name) const { return q[find_field(kHistScalFields, name)]; }

void ContactHistory::configure(unsigned parts) {
  parts_ = parts;
  for (int k = 0; k < kHistVec; ++k) von_[k] = vec_column_enabled(k, parts);
  for (int k = 0; k < kHistScal; ++k) qon_[k] = scal_column_enabled(k, parts);
  assign(0);
}

bool ContactHistory::any_columns() const {
  for (bool b : von_) if (b) return true;
  for (bool b : qon_) if (b) return true;
  return false;
}

void ContactHistory::refresh() {
  for (int k = 0; k < kHistVec; ++k) cols_.v[k] = v_[k].empty() ? nullptr : v_[k].data();
  for (int k = 0; k < kHistScal; ++k) cols_.q[k] = q_[k].empty() ? nullptr : q_[k].data();
}

void ContactHistory::assign(std::size_t rows) {
  active.assign(rows, 0);
  for (int k = 0; k < kHistVec; ++k) {
    if (von_[k]) v_[k].assign(rows, Vec3::Zero());
    else v_[k].clear();
  }
  for (int k = 0; k < kHistScal; ++k) {
    if (qon_[k]) q_[k].assign(rows, 0.0);
    else q_[k].clear();
  }
  refresh();
}

void ContactHistory::swap(ContactHistory& o) {
  std::swap(parts_, o.parts_);
  std::swap(von_, o.von_);
  std::swap(qon_, o.qon_);
  active.swap(o.active);
  for (int k = 0; k < kHistVec; ++k) v_[k].swap(o.v_[k]);
  for (int k = 0; k < kHistScal; ++k) q_[k].swap(o.q_[k]);
  refresh();
  o.refresh();
}

void ContactHistory::copy_row(std::size_t to, const ContactHistory& from, std::size_t q) {
  active[to] = 1;
  for (int k = 0; k < kHistVec; ++k)
    if (von_[k]) v_[k][to] = from.v_[k][q];
  for (int k = 0; k < kHistScal; ++k)
    if (qon_[k]) q_[k][to] = from.q_[k][q];
}

void ContactHistory::set_from(std::size_t to, const HistoryRecord& r, bool flip) {
  active[to] = 1;
  for (int k = 0; k < kHistVec; ++k)
    if (von_[k]) v_[k][to] = (flip && kHistVecFields[k].flips) ? Vec3(-r.v[k]) : r.v[k];
  for (int k = 0; k < kHistScal; ++k)
    if (qon_[k]) q_[k][to] = (flip && kHistScalFields[k].flips) ? -r.q[k] : r.q[k];
}

void ContactHistory::get_into(std::size_t row, HistoryRecord& r) const {
  for (int k = 0; k < kHistVec; ++k)
    if (von_[k]) r.v[k] = v_[k][row];
  for (int k = 0; k < kHistScal; ++k)
    if (qon_[k]) r.q[k] = q_[k][row];
}

double ContactHistory::bytes_per_row() const {
  double b = 1.0;
  for (bool x : von_) b += x ? 24.0 : 0.0;
  for (bool x : qon_) b += x ? 8.0 : 0.0;
  return b;
}

}  // namespace ssdem
