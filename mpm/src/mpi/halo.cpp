/// @file halo.cpp
/// Completion of the held grid nodes after a P2G pass (mpm/mpi/domain.hpp, step 3), over the
/// boxes of the ORB (orb.hpp): rank r holds H_r (its own box O_r grown by H nodes a side) and
/// shares with each other rank q the nodes G_rq = H_r n O_q (held by r, owned by q) and
/// S_rq = O_r n H_q (owned by r, held by q). Two rounds:
///   1. r sends its partial sums of the pass's fields on G_rq to q; the owner forms
///        X_i = X_i^(owner) + X_i^(q_1) + X_i^(q_2) + ...   (the other holders q_1 < q_2 < ...)
///      on its nodes S_rq, a fixed order (a node sits on up to 8 ranks where boxes meet);
///   2. the owner sends X_i on S_rq back to q, which replaces its partial on G_rq with it.
/// Every holder then has the owner's bits. Where only two ranks hold a node this is the one
/// addition X^(r) + X^(q) of the previous one-round slab swap, the same bits on both sides (IEEE
/// addition is commutative): two-rank runs are unchanged.
/// Sparse: a rank sends only the nodes of a shared box whose fields are not all +0 (bit
/// patterns: a -0 is sent), each as its ordinal in that box (the box's nodes in memory order, x
/// fastest: the same global nodes in the same order on both ranks) and its values. A node not
/// received is +0 in every field at the sender: in round 1 the owner adds +0.0 (the dense sum's
/// a + 0 bit for bit), in round 2 the holder sets +0 (the owner's sum was all +0). Most of an
/// impact grid is empty: the halo shrinks to the nodes with mass (plus 8 B of ordinal per node).
/// The velocity drives' node flags go the same way (min_shared_drive: the smallest drive index
/// over the holders, dense), and sum() is the drives' reduction of their reaction impulses.
#include <algorithm>
#include <bit>
#include <cstdint>
#include <stdexcept>

#include "mpm/mpi/domain.hpp"

namespace mpmfrag::mpi {

namespace {
// doubles of a Node per field bit (1 mass, 2 momentum, 4 force) and their offsets in the Node
struct FieldRange {
  int bit, offset, n;
};
constexpr FieldRange kFields[3] = {{1, 0, 1}, {2, 1, 3}, {4, 4, 3}};
static_assert(sizeof(Solver::Node) == 8 * sizeof(double));

/// Visit the local indices (in the held box `held`) of the nodes of global box `b`, in memory
/// order (x fastest).
template <class F>
void for_box(const Box& held, const Box& b, F&& f) {
  const std::size_t sx = static_cast<std::size_t>(held.hi[0] - held.lo[0]);
  const std::size_t sy = static_cast<std::size_t>(held.hi[1] - held.lo[1]);
  for (int k = b.lo[2]; k < b.hi[2]; ++k)
    for (int j = b.lo[1]; j < b.hi[1]; ++j) {
      const std::size_t row = sx * (static_cast<std::size_t>(j - held.lo[1]) + sy * static_cast<std::size_t>(k - held.lo[2]));
      for (int i = b.lo[0]; i < b.hi[0]; ++i) f(row + static_cast<std::size_t>(i - held.lo[0]));
    }
}

int doubles_per_node(int fields) {
  int per = 0;
  for (const FieldRange& f : kFields)
    if (fields & f.bit) per += f.n;
  return per;
}

/// (ordinal, values) of the nodes of `b` whose pass fields are not all +0.
void pack_sparse(const Box& held, const Box& b, const Solver::Node* nodes, int fields, std::vector<double>& out) {
  out.clear();
  std::uint64_t k = 0;
  for_box(held, b, [&](std::size_t i) {
    const double* nd = reinterpret_cast<const double*>(nodes + i);
    bool any = false;
    for (const FieldRange& f : kFields)
      if (fields & f.bit)
        for (int c = 0; c < f.n; ++c) any = any || std::bit_cast<std::uint64_t>(nd[f.offset + c]) != 0;
    if (any) {
      out.push_back(std::bit_cast<double>(k));
      for (const FieldRange& f : kFields)
        if (fields & f.bit) out.insert(out.end(), nd + f.offset, nd + f.offset + f.n);
    }
    ++k;
  });
}

/// Walk a sparse record of box `b`: op(node, values or nullptr) for every node of b in order.
template <class Op>
void unpack_sparse(const Box& held, const Box& b, Solver::Node* nodes, int fields, const std::vector<double>& in, Op&& op) {
  const double* e = in.data();
  const double* end = in.data() + in.size();
  const std::ptrdiff_t per = doubles_per_node(fields);
  std::uint64_t k = 0;
  for_box(held, b, [&](std::size_t i) {
    const bool got = e < end && std::bit_cast<std::uint64_t>(*e) == k;
    if (got && end - e < 1 + per) throw std::logic_error("halo: a truncated sparse record from another rank");
    double* nd = reinterpret_cast<double*>(nodes + i);
    op(nd, got ? e + 1 : nullptr);
    if (got) e += 1 + per;
    ++k;
  });
  if (e != end) throw std::logic_error("halo: another rank's sparse record does not match the shared box");
}

/// Receive one message of unknown length from rank q (tag) into `in`.
template <class T>
void receive(MPI_Comm c, int q, int tag, MPI_Datatype type, std::vector<T>& in) {
  MPI_Status st;
  MPI_Probe(q, tag, c, &st);
  int n = 0;
  MPI_Get_count(&st, type, &n);
  in.resize(static_cast<std::size_t>(n));
  MPI_Recv(in.data(), n, type, q, tag, c, MPI_STATUS_IGNORE);
}
}  // namespace

HaloExchange::Shared HaloExchange::shared() const {
  Shared s;
  const int r = comm_.rank;
  const Box held = orb_.held(r), own = orb_.own()[static_cast<std::size_t>(r)];
  for (int q = 0; q < orb_.ranks(); ++q) {
    if (q == r) continue;
    const Box g = held.intersect(orb_.own()[static_cast<std::size_t>(q)]), m = own.intersect(orb_.held(q));
    if (g.empty() && m.empty()) continue;
    s.rank.push_back(q);
    s.ghost.push_back(g);
    s.mine.push_back(m);
  }
  return s;
}

void HaloExchange::sum_shared(Solver::Node* nodes, int fields) {
  if (comm_.size == 1) return;
  const Shared sh = shared();
  const Box held = orb_.held(comm_.rank);
  const std::size_t n = sh.rank.size();
  send_.resize(2 * n);
  recv_.resize(n);
  std::vector<MPI_Request> req;
  auto post = [&](std::vector<double>& out, int q, int tag) {
    const double bytes = static_cast<double>(sizeof(double) * out.size());
    bytes_sent += bytes;
    comm_.bytes_sent += bytes;
    req.emplace_back();
    MPI_Isend(out.data(), static_cast<int>(out.size()), MPI_DOUBLE, q, tag, comm_.c, &req.back());
  };
  req.reserve(2 * n);
  // 1. the partials of the nodes held here and owned by q go to q; the owner adds them in rank order
  for (std::size_t k = 0; k < n; ++k)
    if (!sh.ghost[k].empty()) {
      pack_sparse(held, sh.ghost[k], nodes, fields, send_[k]);
      post(send_[k], sh.rank[k], 71);
    }
  for (std::size_t k = 0; k < n; ++k)
    if (!sh.mine[k].empty()) {
      receive(comm_.c, sh.rank[k], 71, MPI_DOUBLE, recv_[k]);
      unpack_sparse(held, sh.mine[k], nodes, fields, recv_[k], [&](double* nd, const double* v) {
        for (const FieldRange& f : kFields)
          if (fields & f.bit)
            for (int c = 0; c < f.n; ++c) nd[f.offset + c] += v ? *v++ : 0.0;
      });
    }
  // 2. the owner's sums go back to every holder, which takes them as they are
  for (std::size_t k = 0; k < n; ++k)
    if (!sh.mine[k].empty()) {
      pack_sparse(held, sh.mine[k], nodes, fields, send_[n + k]);
      post(send_[n + k], sh.rank[k], 73);
    }
  for (std::size_t k = 0; k < n; ++k)
    if (!sh.ghost[k].empty()) {
      receive(comm_.c, sh.rank[k], 73, MPI_DOUBLE, recv_[k]);
      unpack_sparse(held, sh.ghost[k], nodes, fields, recv_[k], [&](double* nd, const double* v) {
        for (const FieldRange& f : kFields)
          if (fields & f.bit)
            for (int c = 0; c < f.n; ++c) nd[f.offset + c] = v ? *v++ : 0.0;
      });
    }
  MPI_Waitall(static_cast<int>(req.size()), req.data(), MPI_STATUSES_IGNORE);
}

void HaloExchange::min_shared_drive(std::int32_t* node_drive, std::vector<std::size_t>& added) {
  if (comm_.size == 1) return;
  const Shared sh = shared();
  const Box held = orb_.held(comm_.rank);
  const std::size_t n = sh.rank.size();
  isend_.resize(2 * n);
  irecv_.resize(n);
  std::vector<MPI_Request> req;
  req.reserve(2 * n);
  auto post = [&](std::vector<std::int32_t>& out, int q, int tag) {
    req.emplace_back();
    MPI_Isend(out.data(), static_cast<int>(out.size()), MPI_INT32_T, q, tag, comm_.c, &req.back());
  };
  // the smallest non-negative drive index over the holders (-1: none); `added` gets the nodes
  // whose flag turns from -1 to a drive
  auto take = [&](std::int32_t& mine, std::int32_t theirs) {
    if (theirs < 0 || (mine >= 0 && mine <= theirs)) return;
    if (mine < 0) added.push_back(static_cast<std::size_t>(&mine - node_drive));
    mine = theirs;
  };
  for (std::size_t k = 0; k < n; ++k)
    if (!sh.ghost[k].empty()) {
      isend_[k].clear();
      for_box(held, sh.ghost[k], [&](std::size_t i) { isend_[k].push_back(node_drive[i]); });
      post(isend_[k], sh.rank[k], 72);
    }
  for (std::size_t k = 0; k < n; ++k)
    if (!sh.mine[k].empty()) {
      receive(comm_.c, sh.rank[k], 72, MPI_INT32_T, irecv_[k]);
      if (irecv_[k].size() != static_cast<std::size_t>(sh.mine[k].size()))
        throw std::logic_error("halo: another rank's drive flags do not match the shared box");
      const std::int32_t* in = irecv_[k].data();
      for_box(held, sh.mine[k], [&](std::size_t i) { take(node_drive[i], *in++); });
    }
  for (std::size_t k = 0; k < n; ++k)
    if (!sh.mine[k].empty()) {
      isend_[n + k].clear();
      for_box(held, sh.mine[k], [&](std::size_t i) { isend_[n + k].push_back(node_drive[i]); });
      post(isend_[n + k], sh.rank[k], 74);
    }
  for (std::size_t k = 0; k < n; ++k)
    if (!sh.ghost[k].empty()) {
      receive(comm_.c, sh.rank[k], 74, MPI_INT32_T, irecv_[k]);
      if (irecv_[k].size() != static_cast<std::size_t>(sh.ghost[k].size()))
        throw std::logic_error("halo: another rank's drive flags do not match the shared box");
      const std::int32_t* in = irecv_[k].data();
      for_box(held, sh.ghost[k], [&](std::size_t i) {
        const std::int32_t theirs = *in++;  // the owner's flag: at least as small as this rank's
        std::int32_t& mine = node_drive[i];
        if (mine < 0 && theirs >= 0) added.push_back(i);
        mine = theirs;
      });
    }
  MPI_Waitall(static_cast<int>(req.size()), req.data(), MPI_STATUSES_IGNORE);
}

void HaloExchange::sum(double* v, int n) {
  const std::vector<double> all = comm_.allgather(v, n);
  for (int k = 0; k < n; ++k) v[k] = 0.0;
  for (int q = 0; q < comm_.size; ++q)
    for (int k = 0; k < n; ++k) v[k] += all[static_cast<std::size_t>(q) * n + k];
}

}  // namespace mpmfrag::mpi
