/// @file migrate.cpp
/// Particle records of the domain decomposition (mpm/mpi/domain.hpp, step 1): a particle moves
/// between ranks with ALL its state, i.e. every ParticleSet array (ParticleSet::for_each_array,
/// the one list of per-particle arrays) and every state array of its material's style
/// (StyleInfo::state_fields: the Tonge–Ramesh damage, flaw and granular state included).
///
///   record = material (int32) | the non-empty ParticleSet arrays, for_each_array order |
///            the material's state arrays, state_fields order
///
/// Merging keeps each material's particles contiguous (MaterialSlot ranges): per material the
/// kept particles in index order, then the arrivals in (source rank, sender order).
#include <algorithm>
#include <cstring>
#include <numeric>

#include "mpm/mpi/domain.hpp"

namespace mpmfrag::mpi {

namespace {
void copy_row(const ParticleSet& src, std::size_t i, ParticleSet& dst, std::size_t j) {
  ParticleSet::for_each_array([&](const auto& a) {
    const auto& s = src.*a.member;
    auto& d = dst.*a.member;
    if (s.empty() || d.empty()) return;  // optional array not in use (q)
    const std::size_t w = static_cast<std::size_t>(a.info.width);
    std::copy_n(s.begin() + w * i, w, d.begin() + w * j);
  });
}
std::size_t ncomp(const MaterialSlot& m, std::size_t f) { return static_cast<std::size_t>(m.style->state_fields[f].ncomp); }
}  // namespace

void pack_particle(const ParticleSet& ps, const std::vector<MaterialSlot>& mats, std::size_t p, std::vector<char>& buf) {
  const std::int32_t m = ps.material[p];
  put(buf, m);
  ParticleSet::for_each_array([&](const auto& a) {
    const auto& v = ps.*a.member;
    if (v.empty()) return;
    const std::size_t w = static_cast<std::size_t>(a.info.width), o = buf.size();
    using T = typename std::decay_t<decltype(v)>::value_type;
    buf.resize(o + w * sizeof(T));
    std::memcpy(buf.data() + o, v.data() + w * p, w * sizeof(T));
  });
  const MaterialSlot& s = mats[m];
  for (std::size_t f = 0; f < s.state.size(); ++f) {
    const std::size_t nc = ncomp(s, f), o = buf.size();
    buf.resize(o + nc * sizeof(double));
    std::memcpy(buf.data() + o, s.state[f].data() + nc * (p - s.begin), nc * sizeof(double));
  }
}

void unpack_particles(const std::vector<char>& buf, const std::vector<MaterialSlot>& mats, bool with_q, Arrivals& in) {
  in.index.resize(mats.size());
  in.state.resize(mats.size());
  for (std::size_t m = 0; m < mats.size(); ++m) in.state[m].resize(mats[m].style->state_fields.size());
  std::size_t off = 0;
  while (off < buf.size()) {
    const std::int32_t m = get<std::int32_t>(buf, off);
    in.index[m].push_back(in.ps.size());
    ParticleSet::for_each_array([&](const auto& a) {
      if (a.info.optional && !with_q) return;
      auto& v = in.ps.*a.member;
      using T = typename std::decay_t<decltype(v)>::value_type;
      for (int c = 0; c < a.info.width; ++c) v.push_back(get<T>(buf, off));
    });
    for (std::size_t f = 0; f < in.state[m].size(); ++f)
      for (std::size_t c = 0; c < ncomp(mats[m], f); ++c) in.state[m][f].push_back(get<double>(buf, off));
  }
}

void sort_arrivals(Arrivals& in, const std::vector<std::uint64_t>& key) {
  for (std::size_t m = 0; m < in.index.size(); ++m) {
    std::vector<std::size_t>& idx = in.index[m];
    std::vector<std::size_t> order(idx.size());
    std::iota(order.begin(), order.end(), std::size_t{0});
    std::sort(order.begin(), order.end(), [&](std::size_t x, std::size_t y) { return key[idx[x]] < key[idx[y]]; });
    std::vector<std::size_t> sorted(idx.size());
    for (std::size_t i = 0; i < idx.size(); ++i) sorted[i] = idx[order[i]];
    for (std::vector<double>& st : in.state[m]) {
      const std::size_t nc = idx.empty() ? 0 : st.size() / idx.size();
      std::vector<double> t(st.size());
      for (std::size_t i = 0; i < idx.size(); ++i) std::copy_n(st.begin() + nc * order[i], nc, t.begin() + nc * i);
      st.swap(t);
    }
    idx.swap(sorted);
  }
}

void merge_particles(const ParticleSet& ps, const std::vector<MaterialSlot>& mats, const std::vector<char>& keep,
                     const Arrivals& in, ParticleSet& out, std::vector<MaterialSlot>& out_mats) {
  const bool with_q = !ps.q.empty() || !in.ps.q.empty();
  std::vector<std::size_t> count(mats.size(), 0);
  std::size_t n = 0;
  for (std::size_t m = 0; m < mats.size(); ++m) {
    for (std::size_t p = mats[m].begin; p < mats[m].end; ++p) count[m] += keep[p] ? 1 : 0;
    if (m < in.index.size()) count[m] += in.index[m].size();
    n += count[m];
  }
  out = ParticleSet{};
  out.resize(n, with_q);
  out_mats.clear();
  std::size_t j = 0;
  for (std::size_t m = 0; m < mats.size(); ++m) {
    const MaterialSlot& s = mats[m];
    MaterialSlot t;
    t.name = s.name;
    t.style = s.style;
    t.model = s.model;
    t.extent = s.extent;
    t.begin = j;
    t.end = j + count[m];
    const bool has_state = s.state.size() == s.style->state_fields.size() && !s.state.empty();
    if (has_state) t.state.resize(s.state.size());
    for (std::size_t f = 0; f < t.state.size(); ++f) t.state[f].reserve(ncomp(s, f) * count[m]);
    for (std::size_t p = s.begin; p < s.end; ++p) {
      if (!keep[p]) continue;
      copy_row(ps, p, out, j++);
      for (std::size_t f = 0; f < t.state.size(); ++f) {
        const std::size_t nc = ncomp(s, f);
        t.state[f].insert(t.state[f].end(), s.state[f].begin() + nc * (p - s.begin), s.state[f].begin() + nc * (p - s.begin + 1));
      }
    }
    if (m < in.index.size()) {
      for (const std::size_t k : in.index[m]) copy_row(in.ps, k, out, j++);
      for (std::size_t f = 0; f < t.state.size(); ++f)
        t.state[f].insert(t.state[f].end(), in.state[m][f].begin(), in.state[m][f].end());
    }
    out_mats.push_back(std::move(t));
  }
}

void select_particles(const ParticleSet& ps, const std::vector<MaterialSlot>& mats, const std::vector<char>& keep,
                      ParticleSet& out, std::vector<MaterialSlot>& out_mats) {
  merge_particles(ps, mats, keep, Arrivals{}, out, out_mats);
}

}  // namespace mpmfrag::mpi
