/// @file material_update.cpp
/// The material update of one chunk of particles (after G2P has set L, F and the volume): the
/// material style's stress update (material.hpp contract), then the solver's own energy and
/// artificial viscosity (mpm.md §1.5, Uintah) and the chunk's largest signal speed:
///
///   e_{n+1} = e_n + dt/(2 rho_{n+1}) (sigma_n : L + sigma_{n+1} : L)  +  q |tr D| dt / rho_{n+1}
///   q = rho (A1 c_bulk |tr D| h + A2 (tr D h)^2) if tr D < 0 else 0
///   max_p (s_p + |v_p|) for dt = C min(h) / max_p (s_p + |v_p|), with the signal speed
///   s = Q + sqrt(Q^2 + c_dil^2), Q = A2 h |tr D| where the viscosity acts (tr D < 0), else
///   s = c_dil (c_dil = 0 and Q = 0 for the particles of velocity-driven bodies, which move
///   rigidly: body_drive.hpp). This is the element time step of explicit codes with bulk
///   viscosity, Q = A1 c + A2 h |tr D| (LS-DYNA Theory Manual, "time step control" of solids;
///   Wilkins 1980, J. Comput. Phys. 36:281) [R], without its linear term. Deviation, and why: with
///   A1 c in Q, s jumps by 22 % where tr D changes sign, so a particle whose tr D is zero to
///   round-off would change the step, and the result would depend on the MPI rank count (test
///   mpm_mpi_np2); the linear term alone is a diffusion of number A1 c dt / h <= A1 C = 0.06, far
///   inside its limit. Without Q, the q of a compressing particle can drive a node that carries a
///   small share of its mass (an impactor smaller than a cell) through the compression within one
///   step, and q then does work on the flow (negative shock heat:
///   test EnergyBudget.ArtificialViscosityOnlyDissipatesOnASubCellImpactor).
#include <algorithm>
#include <cmath>
#include <sstream>

#include "kernels.hpp"

namespace mpmfrag {

using namespace detail;

void Solver::run_material_chunk(std::size_t c, double dt, const double* L, double* wpre, double* ws, double* bs,
                                const double* econs) {
  const Chunk ch = chunks_[c];
  const MaterialSlot& slot = mats_[ch.mat];
  const std::size_t n = ch.end - ch.begin;
  double* stress = ps_.stress.data() + 6 * ch.begin;
  // stress power before the update (trapezoidal energy integration)
  for (std::size_t k = 0; k < n; ++k) {
    const double* s = stress + 6 * k;
    const double* l = L + 9 * k;
    wpre[k] = stress_power(s, l);
    wpre[kChunk + k] = (s[0] + s[1] + s[2]) / 3.0 * (l[0] + l[4] + l[8]);  // its volumetric part
  }
  double* sptr[16];
  std::vector<double*> sbig;
  double** sp = sptr;
  if (slot.state.size() > 16) {
    sbig.resize(slot.state.size());
    sp = sbig.data();
  }
  for (std::size_t f = 0; f < slot.state.size(); ++f)
    sp[f] = state_pointer(slot, f, ch.begin);
  MaterialBatch b;
  b.n = n;
  b.first = ch.begin;
  b.dt = dt;
  b.time = time_;
  b.cell_size = h_min_;
  b.seed = cfg_.seed;
  b.L = L;
  b.F = ps_.F.data() + 9 * ch.begin;
  b.stress = stress;
  b.mass = ps_.mass.data() + ch.begin;
  b.volume = ps_.volume.data() + ch.begin;
  b.volume0 = ps_.volume0.data() + ch.begin;
  b.energy = ps_.energy.data() + ch.begin;
  b.id = ps_.id.data() + ch.begin;
  b.x = ps_.x.data() + 3 * ch.begin;
  b.specimen_size = slot.extent;
  b.state = sp;
  b.wave_speed = ws;
  b.bulk_speed = cfg_.artificial_viscosity ? bs : nullptr;
  const BatchResult r = dt > 0.0 ? slot.model->update(b) : (slot.model->initialize(b), BatchResult{});
  std::size_t fails = r.failed;
  std::string msg;
  if (r.failed) {
    const std::size_t p = ch.begin + r.first_failed;
    std::ostringstream os;
    os << "material '" << slot.name << "' (" << slot.style->name << ") failed at particle id " << ps_.id[p] << ": "
       << r.reason;
    msg = os.str();
  }
  double vmax = 0.0;
  double* e = ps_.energy.data() + ch.begin;
  double* q = cfg_.artificial_viscosity ? ps_.q.data() + ch.begin : nullptr;
  const double* v = ps_.v.data() + 3 * ch.begin;
  for (std::size_t k = 0; k < n; ++k) {
    const double* s = stress + 6 * k;
    const double* l = L + 9 * k;
    const double rho = b.mass[k] / b.volume[k];
    const double trD = l[0] + l[4] + l[8];
    const bool consistent = econs != nullptr;
    if (consistent && dt > 0.0) {  // the power of the grid force, computed in G2P (scheme midpoint)
      e[k] += econs[3 * k];
      ps_.work_dev[ch.begin + k] += econs[3 * k + 1];
      ps_.heat_shock[ch.begin + k] += econs[3 * k + 2];
    } else if (dt > 0.0) {
      const double wpost = stress_power(s, l), vpost = (s[0] + s[1] + s[2]) / 3.0 * trD;
      e[k] += 0.5 * dt * (wpre[k] + wpost) / rho;
      ps_.work_dev[ch.begin + k] += 0.5 * dt * (wpre[k] - wpre[kChunk + k] + wpost - vpost) / rho;
    }
    double Q = 0.0;  // the viscous signal speed of the quadratic term, A2 h |tr D| (0 without compression)
    if (q) {
      double qq = 0.0;
      if (trD < 0.0) {
        const double hh = h_min_;
        Q = cfg_.av_a2 * (-trD) * hh;
        qq = rho * (cfg_.av_a1 * bs[k] * (-trD) * hh + Q * (-trD) * hh);
      }
      q[k] = qq;
      if (dt > 0.0 && !consistent) {
        e[k] += qq * (-trD) * dt / rho;
        ps_.heat_shock[ch.begin + k] += qq * (-trD) * dt / rho;
      }
    }
    // a driven body is rigid (its nodes are prescribed, body_drive.hpp): no wave speed in the CFL
    const bool driven = !drives_.empty() && drive_of(b.id[k]) >= 0;
    const double wk = driven ? 0.0 : ws[k], Qk = driven ? 0.0 : Q;
    const double sp2 = (Qk > 0.0 ? Qk + std::sqrt(Qk * Qk + wk * wk) : wk) + std::sqrt(v[3 * k] * v[3 * k] + v[3 * k + 1] * v[3 * k + 1] + v[3 * k + 2] * v[3 * k + 2]);
    const bool finite = std::isfinite(s[0] + s[1] + s[2] + s[3] + s[4] + s[5] + e[k] + sp2);
    if (!finite) {
      if (!fails++) {
        std::ostringstream os;
        os << "non-finite stress/energy/wave speed at particle id " << ps_.id[ch.begin + k] << " (material '" << slot.name << "')";
        msg = os.str();
      }
      continue;
    }
    vmax = std::max(vmax, sp2);
  }
  chunk_speed_[c] = vmax;
  if (fails) {
    chunk_fail_[c] += fails;
    if (chunk_msg_[c].empty()) chunk_msg_[c] = msg;
  }
}

}  // namespace mpmfrag
