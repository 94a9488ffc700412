// The diffusion-decay PDE of the continuous model (layton-intrinsic-slime.md Eq. 1-3) on
// the texture domain: a finite-volume Laplacian over the island texels that measures the
// surface, not the UV sheet. Each island texel is a cell with its lumped 3D area; each
// pair of neighbouring cells (grid neighbours on the same island, and pairs across UV
// seams from the seam correspondence, whether or not gutter texels fit between islands)
// exchanges pheromone through a conductance c_ij = 3D length of the shared face / 3D
// distance between the cell centres (no less than their half-widths: texels on both
// sides of a UV seam sliver sample the same surface). The operator is symmetric, so with r_dec = 0 the
// total amount sum_i A_i u_i is conserved; open boundaries have no faces (closed).
#pragma once
#include <cstdint>
#include <memory>
#include <mutex>
#include <vector>

#include "backends/cpu/thread_pool.h"
#include "domain/texture_domain.h"
#include "surface/surface.h"

namespace moldtex {

struct BackwardEulerSystem;  // texel_laplacian.cpp

// The CPU's pass over the cells in lanes (forward_steps): four cells step together in one
// vector register, each lane adding its own row's terms in the row's order, so every
// lane's result has the bits of the one-row code (shared/pde.h). A row loop waits on its
// chain of additions and on its unpredictable end (rows have 3 to 12 entries); four rows
// padded to the longest of them do not. Chunk c holds the cells cell[4c .. 4c + 4) with
// slots first[c] .. first[c + 1], each slot one entry per lane (col, weight; a lane past
// its row's end has its own cell and conductance 0, which adds exactly +0). With local
// time stepping the chunks hold every cell that is not fine; a border cell's entries
// towards fine cells are left out (mtx_coarse_cell skips them too) and what its fine
// neighbours drew from it is summed first, in its row's order, into drawn[its lane]
// (border_lane; the compact entries border_link[border_start[b] .. border_start[b + 1]]).
// `lone` lists the last few rows when the count is not a multiple of 4 (stepped one at a
// time).
struct CoarseLanes {
  std::vector<uint32_t> cell, first, col, lone;
  std::vector<float> weight, area;
  std::vector<uint32_t> border_lane, border_start, border_link;
  mutable std::vector<float> drawn;  // per lane; 0 but for border cells
  size_t chunks() const { return first.empty() ? 0 : first.size() - 1; }
};

// Local time stepping for forward Euler: most cells are stable with a sub-step of h, a few
// stiff ones (texels that are small in 3D: UV poles, pinched or squeezed UVs) need much
// shorter ones. Rather than sub-stepping every cell for the stiffest, a step runs
// `coarse` sub-steps, and within each the fine cells run `fine` shorter ones against
// their coarse neighbours' values at the coarse sub-step's start; the flux through each
// coarse-fine face is summed on the fine side and taken once from the coarse side, so
// the total is conserved exactly as with global steps (shared/pde.h).
struct LocalSteppingPlan {
  double rdt = -1;                 // r_dif dt it was made for
  uint32_t coarse = 1, fine = 1;   // coarse sub-steps per step; fine ones per coarse one
  std::vector<uint32_t> fine_rows; // the fine cells (row indices); empty: global steps
  std::vector<uint8_t> step_class; // per texel: MTX_STEP_COARSE, _FINE or _BORDER (shared/pde.h)
  // The fine cells' own compact rows (shared/pde.h, mtx_fine_cell): fine cell f (texel
  // fine_cell[f], area fine_area[f]) has entries fine_start[f] .. fine_start[f + 1], each a
  // neighbour fine_nbr[e] and its conductance fine_weight[e]. link (per CSR entry): for
  // an entry (border cell -> fine cell), the compact entry back (0 elsewhere).
  std::vector<uint32_t> fine_cell, fine_start, fine_nbr, link;
  std::vector<float> fine_area, fine_weight;
  // Scratch of the CPU stepping: fine cells' values (per fine cell) and inflows (per
  // compact entry).
  mutable std::vector<float> cur, next, flux;
  // The CPU's lanes for this plan, made on the first forward Euler step (the OpenCL
  // backend does not use them).
  mutable std::shared_ptr<const CoarseLanes> lanes;
};

struct TexelLaplacian {
  // Island texels (the cells), in texel order.
  std::vector<uint32_t> rows;
  // CSR over rows: cell rows[r] exchanges with texels col[start[r] .. start[r + 1]) with
  // conductances weight[...] (dimensionless). Symmetric: (i, j, c) iff (j, i, c).
  std::vector<uint32_t> start, col;
  std::vector<float> weight;
  // Per texel (texel_count): the cell's lumped 3D area (0 for texels that are not cells).
  std::vector<float> area;
  double max_rate = 0;    // max over cells of sum_j c_ij / A_i (1 / mesh units^2)
  double total_area = 0;  // sum of the cell areas
  // Per row: its rate sum_j c_ij / A_i.
  std::vector<float> rate;
  // The rates, ascending: local time stepping weighs how many cells each sub-step leaves
  // too stiff.
  std::vector<float> sorted_rate;
  mutable std::shared_ptr<LocalSteppingPlan> local;  // for the last r_dif dt (cache)

  // Memory held, with the local time stepping plan (not backward Euler's matrix).
  size_t bytes() const;
  // Backward Euler's matrix M + r_dif dt K for the last r_dif dt used, built on first use
  // (advance_diffusion_decay). Treat the fields above as immutable once built: copies
  // share this cache.
  mutable std::shared_ptr<BackwardEulerSystem> backward;
  // Taken by a step and by the caches' updates: copies share it with the caches, and two
  // simulations on one cached domain (intrinsic_domain_for) may step at once, where the
  // plan's scratch and its lazily made parts would otherwise be written by both.
  mutable std::shared_ptr<std::recursive_mutex> guard = std::make_shared<std::recursive_mutex>();
  // The guard, held until the returned lock goes (none for a moved-from Laplacian).
  std::unique_lock<std::recursive_mutex> lock() const {
    return guard ? std::unique_lock<std::recursive_mutex>(*guard) : std::unique_lock<std::recursive_mutex>();
  }
};

// The CSR entry (j -> i) of entry k (i -> j) of row r, i = rows[r] (found by bisection:
// rows and each row's columns are in texel order; not stored, 4 bytes per entry, since
// only building a local time stepping plan and tests need it).
uint32_t reverse_entry(const TexelLaplacian& lap, uint32_t r, uint32_t k);

TexelLaplacian build_texel_laplacian(const Surface& surface, const TextureDomain& domain,
                                     ThreadPool& pool);

// A face between cells lo and hi with conductance c (each pair once).
struct CellEdge {
  uint32_t lo, hi;
  float c;
};
// The operator of any cell graph: `area` per cell index (area.size() indices, 0 for
// indices that are not cells), `rows` the cells in ascending order, `edges` between
// cells. The texture domain's texels and the intrinsic domain's vertices
// (domain/intrinsic_domain.h) both become one.
TexelLaplacian laplacian_from_edges(std::vector<uint32_t> rows, std::vector<float> area,
                                    const std::vector<CellEdge>& edges);

// The operator with a diffusion-rate map (Eq. 6's per-element R_dif): each face's
// conductance times the mean of its two cells' factors (per texel, >= 0); still
// symmetric, so still conservative. Rates and caches are made anew.
TexelLaplacian with_diffusion_map(const TexelLaplacian& base, const std::vector<float>& factor);

struct PdeStepInfo {
  uint32_t substeps = 0;    // forward Euler sub-steps taken (0 if backward)
  uint32_t iterations = 0;  // conjugate-gradient iterations (0 if forward)
  bool backward = false;
};

// Forward-Euler (coarse) sub-steps per step: local_stepping_plan(...).coarse.
uint32_t forward_substeps(const TexelLaplacian& lap, double r_dif, double dt);

// The local time stepping plan for r_dif dt (cached in lap.local): the coarse sub-step
// count with the least work (every cell once per coarse sub-step, the cells too stiff for
// it `fine` times, enough for max_rate); with one cell stiffness it is global sub-steps.
const LocalSteppingPlan& local_stepping_plan(const TexelLaplacian& lap, double r_dif, double dt);

// Whether a step runs backward Euler: BACKWARD, or AUTO beyond 64 forward sub-steps.
// Throws INVALID_ARGUMENT for FORWARD beyond 256 sub-steps (with what to do instead) and
// for an unknown integrator.
bool use_backward_euler(const TexelLaplacian& lap, double r_dif, double dt, uint32_t integrator);

// Advances u (texel_count floats; only cells are read and written) by dt of
// du/dt = r_dif L u - r_dec u. `integrator` is a moldtex_integrator. Decay is applied
// exactly (u *= exp(-r_dec dt)) after the diffusion. Deterministic for any thread count.
PdeStepInfo advance_diffusion_decay(const TexelLaplacian& lap, float* u,
                                    std::vector<float>& scratch, double r_dif, double r_dec,
                                    double dt, uint32_t integrator, ThreadPool& pool);

// sum_i A_i u_i over the cells, in double.
double total_amount(const TexelLaplacian& lap, const float* u);

}  // namespace moldtex
