#include "domain/texel_laplacian.h"

#include <Eigen/IterativeLinearSolvers>
#include <Eigen/SparseCore>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <string>
#include <utility>

#include "common/error.h"
#include "domain/seam_neighbours.h"
#include "shared/pde.h"

namespace moldtex {

// Backward Euler's system for one r_dif dt: the matrix M + h K in double and the
// conjugate-gradient solver that holds a reference to it (so the struct never moves: it
// lives behind TexelLaplacian::backward).
struct BackwardEulerSystem {
  using Matrix = Eigen::SparseMatrix<double>;
  double h = -1;
  Matrix matrix;
  // Lower | Upper: the product uses the whole (symmetric) matrix, no triangular trick.
  // Eigen runs it single-threaded here (no OpenMP), so the result is deterministic.
  Eigen::ConjugateGradient<Matrix, Eigen::Lower | Eigen::Upper, Eigen::DiagonalPreconditioner<double>>
      solver;
};

namespace {

// Forward Euler sub-step length: h * max_rate <= 0.9. Below 1 every update is a convex
// combination of the cell and its neighbours (u_i's weight 1 - h sum_j c_ij / A_i >= 0.1),
// so it is stable and monotone: no oscillation, no overshoot, no negative values.
// (Plain stability would allow up to 2 / largest eigenvalue of M^-1 K, itself between
// max_rate and 2 max_rate by Gershgorin; the margin costs at most 2x sub-steps.)
constexpr double kForwardLimit = 0.9;
constexpr uint32_t kMaxForwardSubsteps = 256;  // beyond this, refuse forward Euler
// AUTO switches to backward Euler beyond this: measured on the 512^2 UV sphere (its pole fans
// need 37 sub-steps), forward Euler took 35 ms a step and backward Euler 90 ms, so forward
// wins up to about 90 sub-steps.
constexpr uint32_t kAutoForwardSubsteps = 64;
constexpr double kBackwardTolerance = 1e-6;    // CG: |b - A x| <= tol |b|
// Local time stepping: the fine cells' sub-steps per coarse one are bounded (beyond:
// backward Euler, or refused); a fine cell's sub-step costs about this many coarse
// cells' (it also sums its inflows), which the choice of the coarse sub-step weighs.
constexpr uint32_t kMaxFineSubsteps = 1024;
constexpr double kFineCellCost = 1.5;
constexpr size_t kRowGrain = 4096;             // rows per parallel_for chunk

using Vec3d = std::array<double, 3>;

Vec3d sub(const Vec3d& a, const Vec3d& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
double dot(const Vec3d& a, const Vec3d& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
double length(const Vec3d& a) { return std::sqrt(dot(a, a)); }

// A triangle's affine map from UV to 3D: P(u, v) = origin + (u - u0) du + (v - v0) dv.
struct UvTo3d {
  Vec3d origin{}, du{}, dv{};
  double u0 = 0, v0 = 0;
};

UvTo3d uv_to_3d(const Surface& s, uint32_t t) {
  UvTo3d m;
  const float* uv = &s.corner_uvs[6 * t];
  Vec3d p[3];
  for (int c = 0; c < 3; ++c)
    for (int k = 0; k < 3; ++k) p[c][k] = s.positions[3 * s.triangles[3 * t + c] + k];
  // J = E T^-1 with E = [p1 - p0, p2 - p0] and T the matching UV differences.
  const double t00 = uv[2] - uv[0], t01 = uv[4] - uv[0], t10 = uv[3] - uv[1], t11 = uv[5] - uv[1];
  const double det = t00 * t11 - t01 * t10;
  m.origin = p[0];
  m.u0 = uv[0];
  m.v0 = uv[1];
  if (det == 0.0) return m;  // degenerate: owns no texels
  const Vec3d e1 = sub(p[1], p[0]), e2 = sub(p[2], p[0]);
  for (int k = 0; k < 3; ++k) {
    m.du[k] = (e1[k] * t11 - e2[k] * t10) / det;
    m.dv[k] = (e2[k] * t00 - e1[k] * t01) / det;
  }
  return m;
}

// What a cell contributes to its faces: its centre in 3D and its texel's two 3D edge
// vectors, a (one texel along x) and b (one texel along y). |a| and |b| are
// 1 / texels_per_unit of the domain, computed here in double.
struct CellGeometry {
  Vec3d centre{}, a{}, b{};
};

CellGeometry cell_geometry(const TextureDomain& d, const std::vector<UvTo3d>& maps, uint32_t i) {
  const UvTo3d& m = maps[d.texel_triangle[i]];
  const uint32_t x = i % d.width, y = i / d.width;
  const double W = d.width, H = d.height;
  const double u = (x + 0.5) / W - m.u0, v = (y + 0.5) / H - m.v0;
  CellGeometry g;
  for (int k = 0; k < 3; ++k) {
    g.centre[k] = m.origin[k] + u * m.du[k] + v * m.dv[k];
    g.a[k] = m.du[k] / W;
    g.b[k] = m.dv[k] / H;
  }
  return g;
}

// One side's estimate of the conductance of the pair (lo, hi).
struct Proposal {
  uint32_t lo, hi, from;
  bool grid;  // a grid edge on one island (seam-correspondence proposals defer to it)
  double c;
  bool operator<(const Proposal& o) const {
    if (lo != o.lo) return lo < o.lo;
    if (hi != o.hi) return hi < o.hi;
    if (from != o.from) return from < o.from;
    if (grid != o.grid) return grid > o.grid;
    return c < o.c;
  }
};

// The conductance one cell estimates for the face it shares with `other` in direction k
// (0 W, 1 E, 2 S, 3 N): the 3D length of the face, averaged over both cells, over the 3D
// distance between the centres. A cell's face across x is its texel's y edge |b| and its
// width along the crossing is |a|, and vice versa across y. The other cell of a grid
// edge has the same texel axes; across a seam its axes may be turned (islands rotated in
// UV), so for it the crossing runs along whichever of its axes is closer to the line
// between the centres.
//
// The distance is at least the two half-widths along the crossing, as on a regular grid.
// Centres can be closer only where both texels sample the same bit of surface: on either
// side of a UV seam sliver (the gaps between a UV sphere's pole fans are grid-adjacent
// texels of one island only a fraction of a texel apart in 3D) or at a seam neighbour
// that the walk found off-centre. Coupling such a pair harder than neighbours that
// touch would add nothing but stiffness (forward Euler sub-steps).
double conductance(const CellGeometry& self, const CellGeometry& other, int k, bool grid) {
  const bool across_x = k < 2;
  const double own_face = length(across_x ? self.b : self.a);
  const double own_width = length(across_x ? self.a : self.b);
  const Vec3d e = sub(other.centre, self.centre);
  double other_face, other_width;
  bool other_across_x = across_x;
  if (!grid) {
    const double la = length(other.a), lb = length(other.b);
    const double along_a = la > 0 ? std::fabs(dot(e, other.a)) / la : 0.0;
    const double along_b = lb > 0 ? std::fabs(dot(e, other.b)) / lb : 0.0;
    other_across_x = along_a >= along_b;
  }
  other_face = length(other_across_x ? other.b : other.a);
  other_width = length(other_across_x ? other.a : other.b);
  const double distance = std::max(length(e), 0.5 * (own_width + other_width));
  return 0.5 * (own_face + other_face) / distance;
}

// Grid neighbour of cell i (x, y) in direction k if it is a cell of i's island, else i.
uint32_t island_grid_neighbour(const Surface& s, const TextureDomain& d, uint32_t x, uint32_t y,
                               int k) {
  const uint32_t i = y * d.width + x;
  const uint32_t n = grid_neighbour(d, x, y, k);
  if (n == i || d.classes[n] != MOLDTEX_TEXEL_INSIDE) return i;
  return s.island[d.texel_triangle[n]] == s.island[d.texel_triangle[i]] ? n : i;
}

// Is j one of cell i's grid neighbours on its own island (so the grid edge covers it)?
bool grid_linked(const Surface& s, const TextureDomain& d, uint32_t i, uint32_t j) {
  const uint32_t x = i % d.width, y = i / d.width;
  for (int k = 0; k < 4; ++k)
    if (island_grid_neighbour(s, d, x, y, k) == j && j != i) return true;
  return false;
}

// Every side's proposals for the edges of the cells in texture row y.
void propose_row(const Surface& s, const TextureDomain& d, const std::vector<UvTo3d>& maps,
                 uint32_t y, std::vector<Proposal>& out) {
  for (uint32_t x = 0; x < d.width; ++x) {
    const uint32_t i = y * d.width + x;
    if (d.classes[i] != MOLDTEX_TEXEL_INSIDE) continue;
    const CellGeometry gi = cell_geometry(d, maps, i);
    // The seam correspondence lists texels in texel order.
    const auto seam = std::lower_bound(d.seam_texel.begin(), d.seam_texel.end(), i);
    const bool at_seam = seam != d.seam_texel.end() && *seam == i;
    const uint32_t* across = at_seam ? &d.seam_neighbour[4 * (seam - d.seam_texel.begin())] : nullptr;
    for (int k = 0; k < 4; ++k) {
      uint32_t j = island_grid_neighbour(s, d, x, y, k);
      bool grid = j != i;
      if (!grid) {
        if (!across) continue;
        j = across[k];
        // Self (open boundary, reflected walk), not a cell, or already a grid edge.
        if (j == i || d.classes[j] != MOLDTEX_TEXEL_INSIDE || grid_linked(s, d, i, j)) continue;
      }
      const double c = conductance(gi, cell_geometry(d, maps, j), k, grid);
      out.push_back({std::min(i, j), std::max(i, j), i, grid, c});
    }
  }
}


// One symmetric conductance per pair: a grid edge's two (equal-rule) estimates
// averaged; across a seam, each side's estimates averaged, then the two sides averaged
// (the correspondence is not always mutual, so a side may be missing).
std::vector<CellEdge> merge(std::vector<Proposal>& proposals) {
  std::sort(proposals.begin(), proposals.end());
  std::vector<CellEdge> edges;
  for (size_t a = 0; a < proposals.size();) {
    size_t b = a;
    bool grid = false;
    while (b < proposals.size() && proposals[b].lo == proposals[a].lo && proposals[b].hi == proposals[a].hi)
      grid |= proposals[b++].grid;
    double sum = 0;
    int sides = 0;
    for (size_t p = a; p < b;) {
      const uint32_t from = proposals[p].from;
      double side = 0;
      int n = 0;
      for (; p < b && proposals[p].from == from; ++p)
        if (proposals[p].grid == grid) {
          side += proposals[p].c;
          ++n;
        }
      if (n) {
        sum += side / n;
        ++sides;
      }
    }
    edges.push_back({proposals[a].lo, proposals[a].hi, static_cast<float>(sum / sides)});
    a = b;
  }
  return edges;
}

uint32_t row_of(const TexelLaplacian& lap, uint32_t texel) {
  return static_cast<uint32_t>(std::lower_bound(lap.rows.begin(), lap.rows.end(), texel) - lap.rows.begin());
}

void prepare_backward(const TexelLaplacian& lap, double h) {
  if (!lap.backward) lap.backward = std::make_shared<BackwardEulerSystem>();
  BackwardEulerSystem& sys = *lap.backward;
  if (sys.h == h) return;
  const size_t n = lap.rows.size();
  std::vector<Eigen::Triplet<double>> entries;
  entries.reserve(n + lap.col.size());
  for (size_t r = 0; r < n; ++r) {
    double diagonal = lap.area[lap.rows[r]];
    for (uint32_t k = lap.start[r]; k < lap.start[r + 1]; ++k) {
      entries.emplace_back(static_cast<int>(r), static_cast<int>(row_of(lap, lap.col[k])), -h * lap.weight[k]);
      diagonal += h * lap.weight[k];
    }
    entries.emplace_back(static_cast<int>(r), static_cast<int>(r), diagonal);
  }
  sys.matrix.resize(static_cast<Eigen::Index>(n), static_cast<Eigen::Index>(n));
  sys.matrix.setFromTriplets(entries.begin(), entries.end());
  sys.solver.setTolerance(kBackwardTolerance);
  sys.solver.compute(sys.matrix);
  sys.h = h;
}

// Backward Euler (Eq. 3 without the decay term): (M + h K) u' = M u, warm-started from
// u. Returns the CG iterations.
uint32_t backward_step(const TexelLaplacian& lap, float* u, double h, double decay) {
  prepare_backward(lap, h);
  BackwardEulerSystem& sys = *lap.backward;
  const size_t n = lap.rows.size();
  Eigen::VectorXd rhs(n), guess(n);
  for (size_t r = 0; r < n; ++r) {
    guess[r] = u[lap.rows[r]];
    rhs[r] = lap.area[lap.rows[r]] * guess[r];
  }
  const Eigen::VectorXd solution = sys.solver.solveWithGuess(rhs, guess);
  if (sys.solver.info() != Eigen::Success)
    fail(MOLDTEX_ERROR_INTERNAL, "Backward Euler: conjugate gradients did not converge in " +
                                     std::to_string(sys.solver.iterations()) + " iterations");
  // The exact solution of this M-matrix system is non-negative; conjugate gradients stop
  // within a tolerance and may leave tiny negative values where u is near zero (seen on a
  // fuzzed sliver mesh: -1e-14). A concentration is never negative, so clamp them.
  for (size_t r = 0; r < n; ++r) u[lap.rows[r]] = static_cast<float>(std::max(0.0, solution[r]) * decay);
  return static_cast<uint32_t>(sys.solver.iterations());
}

// The plan's lanes (CoarseLanes): every cell that is not fine, in chunks of 4 in row
// order.
const CoarseLanes& coarse_lanes(const TexelLaplacian& lap, const LocalSteppingPlan& plan) {
  if (plan.lanes) return *plan.lanes;
  auto lanes = std::make_shared<CoarseLanes>();
  const bool local = !plan.fine_rows.empty();
  auto fine = [&](uint32_t texel) { return local && plan.step_class[texel] == MTX_STEP_FINE; };
  std::array<uint32_t, 4> pending{};
  std::array<uint32_t, 4> length{};
  size_t count = 0;
  std::array<std::vector<uint32_t>, 4> entries;  // each lane's entries, less those towards fine cells
  // Rows of about equal length: a little padding (Suzanne's intrinsic domain: 14 %).
  lanes->col.reserve(lap.col.size() + lap.col.size() / 4);
  lanes->weight.reserve(lanes->col.capacity());
  lanes->first.push_back(0);
  lanes->border_start.push_back(0);
  for (size_t r = 0; r < lap.rows.size(); ++r) {
    if (fine(lap.rows[r])) continue;
    pending[count++] = static_cast<uint32_t>(r);
    if (count < 4) continue;
    count = 0;
    for (size_t l = 0; l < 4; ++l) {
      const uint32_t q = pending[l];
      const size_t links = lanes->border_link.size();
      entries[l].clear();
      for (uint32_t k = lap.start[q]; k < lap.start[q + 1]; ++k) {
        if (fine(lap.col[k]))
          lanes->border_link.push_back(plan.link[k]);
        else
          entries[l].push_back(k);
      }
      if (lanes->border_link.size() > links) {  // a border cell
        lanes->border_lane.push_back(static_cast<uint32_t>(lanes->cell.size()));
        lanes->border_start.push_back(static_cast<uint32_t>(lanes->border_link.size()));
      }
      length[l] = static_cast<uint32_t>(entries[l].size());
      lanes->cell.push_back(lap.rows[q]);
      lanes->area.push_back(lap.area[lap.rows[q]]);
    }
    const uint32_t longest = *std::max_element(length.begin(), length.end());
    for (uint32_t k = 0; k < longest; ++k)
      for (size_t l = 0; l < 4; ++l) {
        const bool real = k < length[l];
        lanes->col.push_back(real ? lap.col[entries[l][k]] : lap.rows[pending[l]]);
        lanes->weight.push_back(real ? lap.weight[entries[l][k]] : 0.f);
      }
    lanes->first.push_back(static_cast<uint32_t>(lanes->col.size() / 4));
  }
  for (size_t q = 0; q < count; ++q) lanes->lone.push_back(pending[q]);
  lanes->col.shrink_to_fit();
  lanes->weight.shrink_to_fit();
  lanes->cell.shrink_to_fit();
  lanes->area.shrink_to_fit();
  lanes->first.shrink_to_fit();
  lanes->drawn.assign(lanes->cell.size(), 0.f);
  plan.lanes = lanes;
  return *lanes;
}

// Chunks begin .. end of the lanes, one sub-step of length h (decay d): each lane computes
// mtx_diffuse_cell's expression (`global`: no fine cells) or mtx_coarse_cell's, the same
// operations in the same order, so the same bits (a lane that is not a border cell has
// drawn 0, and x - 0 is x).
typedef float Lanes4 __attribute__((vector_size(16)));
template <bool global>
void step_lanes(const CoarseLanes& lanes, const float* in, float* out, float h, float d, size_t begin,
                size_t end) {
  const uint32_t *cell = lanes.cell.data(), *first = lanes.first.data(), *col = lanes.col.data();
  const float *weight = lanes.weight.data(), *area = lanes.area.data(), *drawn = lanes.drawn.data();
  for (size_t c = begin; c < end; ++c) {
    const uint32_t* x = cell + 4 * c;
    const Lanes4 ui = {in[x[0]], in[x[1]], in[x[2]], in[x[3]]};
    Lanes4 total = {0.f, 0.f, 0.f, 0.f};
    for (uint32_t slot = first[c]; slot < first[c + 1]; ++slot) {
      const uint32_t* j = col + 4 * slot;
      const Lanes4 uj = {in[j[0]], in[j[1]], in[j[2]], in[j[3]]};
      Lanes4 w;
      std::memcpy(&w, weight + 4 * slot, sizeof w);
      total = total + w * (uj - ui);
    }
    Lanes4 a;
    std::memcpy(&a, area + 4 * c, sizeof a);
    Lanes4 next;
    if (global) {
      next = (ui + h / a * total) * d;
    } else {
      Lanes4 taken;
      std::memcpy(&taken, drawn + 4 * c, sizeof taken);
      next = (ui + (h * total - taken) / a) * d;
    }
    for (int l = 0; l < 4; ++l) out[x[l]] = next[l];
  }
}

// Forward Euler (Eq. 2) in n sub-steps between u and scratch; the last one applies decay.
// With fine cells in `plan`, each sub-step is local time stepping (LocalSteppingPlan).
void forward_steps(const TexelLaplacian& lap, const LocalSteppingPlan& plan, float* u,
                   std::vector<float>& scratch, double h, uint32_t n, double decay, ThreadPool& pool) {
  if (scratch.size() < lap.area.size()) scratch.resize(lap.area.size());
  float* in = u;
  float* out = scratch.data();
  const float hf = static_cast<float>(h);
  const bool local = !plan.fine_rows.empty();
  // Fine cells' current and next values and their inflows (compact: shared/pde.h).
  std::vector<float>& cur = plan.cur;
  std::vector<float>& next = plan.next;
  std::vector<float>& flux = plan.flux;
  if (local) {
    cur.resize(plan.fine_cell.size());
    next.resize(plan.fine_cell.size());
    flux.resize(plan.fine_nbr.size());
  }
  const float hfine = static_cast<float>(h / plan.fine);
  const CoarseLanes& lanes = coarse_lanes(lap, plan);
  const size_t chunks = lanes.chunks(), lone_count = lanes.lone.size();
  // One pass over the chunks (indices 0 .. chunks) and the lone rows (after them).
  const size_t grain = kRowGrain / 4;
  for (uint32_t step = 0; step < n; ++step) {
    const float d = step + 1 == n ? static_cast<float>(decay) : 1.f;
    // The tables as plain pointers captured by value: the compiler keeps them in
    // registers over the loop instead of reloading them through the closure per row.
    const mtx_u32 *rows = lap.rows.data(), *start = lap.start.data(), *col = lap.col.data(),
                  *link = plan.link.data(), *lone = lanes.lone.data();
    const float *weight = lap.weight.data(), *area = lap.area.data(), *inflow = flux.data(), *from = in;
    const mtx_u8* step_class = plan.step_class.data();
    const CoarseLanes* lanes_ptr = &lanes;
    float* to = out;
    if (!local) {
      pool.parallel_for(chunks + lone_count, grain, [=](size_t begin, size_t end) {
        step_lanes<true>(*lanes_ptr, from, to, hf, d, std::min(begin, chunks), std::min(end, chunks));
        for (size_t q = std::max(begin, chunks); q < end; ++q) {
          const mtx_u32 r = lone[q - chunks];
          to[rows[r]] = mtx_diffuse_cell(rows, start, col, weight, area, from, r, hf, d);
        }
      });
      std::swap(in, out);
      continue;
    }
    const size_t fine_count = plan.fine_cell.size();
    for (size_t f = 0; f < fine_count; ++f) cur[f] = in[plan.fine_cell[f]];
    std::fill(flux.begin(), flux.end(), 0.f);
    for (uint32_t q = 0; q < plan.fine; ++q) {
      pool.parallel_for(fine_count, 256, [&](size_t begin, size_t end) {
        for (size_t f = begin; f < end; ++f)
          next[f] = mtx_fine_cell(plan.fine_start.data(), plan.fine_nbr.data(), plan.fine_weight.data(),
                                  plan.fine_area.data(), in, cur.data(), flux.data(), static_cast<mtx_u32>(f),
                                  hfine);
      });
      std::swap(cur, next);
    }
    // What the fine cells drew from each border cell, in its row's order (mtx_coarse_cell).
    float* drawn = lanes.drawn.data();
    for (size_t b = 0; b < lanes.border_lane.size(); ++b) {
      float sum = 0.f;
      for (uint32_t e = lanes.border_start[b]; e < lanes.border_start[b + 1]; ++e) sum += inflow[lanes.border_link[e]];
      drawn[lanes.border_lane[b]] = sum;
    }
    pool.parallel_for(chunks + lone_count, grain, [=](size_t begin, size_t end) {
      step_lanes<false>(*lanes_ptr, from, to, hf, d, std::min(begin, chunks), std::min(end, chunks));
      for (size_t q = std::max(begin, chunks); q < end; ++q) {
        const mtx_u32 r = lone[q - chunks];
        to[rows[r]] = mtx_coarse_cell(rows, start, col, weight, area, step_class, link, from, inflow, r, hf, d);
      }
    });
    for (size_t f = 0; f < fine_count; ++f) out[plan.fine_cell[f]] = cur[f] * d;
    std::swap(in, out);
  }
  if (in != u)
    pool.parallel_for(lap.rows.size(), kRowGrain, [&](size_t begin, size_t end) {
      for (size_t r = begin; r < end; ++r) u[lap.rows[r]] = in[lap.rows[r]];
    });
}

}  // namespace

uint32_t reverse_entry(const TexelLaplacian& lap, uint32_t r, uint32_t k) {
  const uint32_t j = static_cast<uint32_t>(std::lower_bound(lap.rows.begin(), lap.rows.end(), lap.col[k]) -
                                           lap.rows.begin());
  const auto first = lap.col.begin() + lap.start[j], last = lap.col.begin() + lap.start[j + 1];
  return static_cast<uint32_t>(std::lower_bound(first, last, lap.rows[r]) - lap.col.begin());
}

TexelLaplacian laplacian_from_edges(std::vector<uint32_t> rows, std::vector<float> area,
                                    const std::vector<CellEdge>& edges) {
  TexelLaplacian lap;
  lap.rows = std::move(rows);
  lap.area = std::move(area);
  for (uint32_t i : lap.rows) lap.total_area += lap.area[i];

  // Symmetric CSR: each edge in both rows, each row's columns in texel order.
  const size_t n = lap.rows.size();
  std::vector<uint32_t> row_index(lap.area.size(), 0);
  for (size_t r = 0; r < n; ++r) row_index[lap.rows[r]] = static_cast<uint32_t>(r);
  lap.start.assign(n + 1, 0);
  for (const CellEdge& e : edges) {
    ++lap.start[row_index[e.lo] + 1];
    ++lap.start[row_index[e.hi] + 1];
  }
  for (size_t r = 0; r < n; ++r) lap.start[r + 1] += lap.start[r];
  lap.col.resize(lap.start[n]);
  lap.weight.resize(lap.start[n]);
  std::vector<uint32_t> fill(lap.start.begin(), lap.start.end() - 1);
  for (const CellEdge& e : edges) {  // edges are sorted by (lo, hi)
    uint32_t k = fill[row_index[e.lo]]++;
    lap.col[k] = e.hi;
    lap.weight[k] = e.c;
    k = fill[row_index[e.hi]]++;
    lap.col[k] = e.lo;
    lap.weight[k] = e.c;
  }
  for (size_t r = 0; r < n; ++r) {
    std::vector<std::pair<uint32_t, float>> entries;
    for (uint32_t k = lap.start[r]; k < lap.start[r + 1]; ++k) entries.push_back({lap.col[k], lap.weight[k]});
    std::sort(entries.begin(), entries.end());
    double rate = 0;
    for (size_t k = 0; k < entries.size(); ++k) {
      lap.col[lap.start[r] + k] = entries[k].first;
      lap.weight[lap.start[r] + k] = entries[k].second;
      rate += entries[k].second;
    }
    lap.max_rate = std::max(lap.max_rate, rate / lap.area[lap.rows[r]]);
    lap.rate.push_back(static_cast<float>(rate / lap.area[lap.rows[r]]));
  }
  lap.sorted_rate = lap.rate;
  std::sort(lap.sorted_rate.begin(), lap.sorted_rate.end());
  return lap;
}

TexelLaplacian build_texel_laplacian(const Surface& s, const TextureDomain& d, ThreadPool& pool) {
  TexelLaplacian lap;
  std::vector<UvTo3d> maps(s.triangle_count());
  for (uint32_t t = 0; t < s.triangle_count(); ++t) maps[t] = uv_to_3d(s, t);

  // Cells and their lumped areas: the 3D area of the texel under its centre's triangle.
  const double per_texel = 1.0 / (static_cast<double>(d.width) * d.height);
  lap.area.assign(d.texel_count(), 0.f);
  std::vector<uint8_t> is_cell(d.texel_count(), 0);
  for (uint32_t i = 0; i < d.texel_count(); ++i) {
    if (d.classes[i] != MOLDTEX_TEXEL_INSIDE) continue;
    const float area = static_cast<float>(s.area_per_uv_area(d.texel_triangle[i]) * per_texel);
    // A texel whose centre lies on a triangle degenerate in UV (or in 3D) covers no
    // measurable surface: no cell (it would divide by 0), and no edges below.
    if (!(area > 0.f && std::isfinite(area))) continue;
    is_cell[i] = 1;
    lap.rows.push_back(i);
    lap.area[i] = area;
  }

  // Proposals per texture row, joined in row order: the same list for any thread count.
  std::vector<std::vector<Proposal>> per_row(d.height);
  pool.parallel_for(d.height, 8, [&](size_t begin, size_t end) {
    for (size_t y = begin; y < end; ++y) propose_row(s, d, maps, static_cast<uint32_t>(y), per_row[y]);
  });
  std::vector<Proposal> proposals;
  for (auto& row : per_row) proposals.insert(proposals.end(), row.begin(), row.end());
  per_row.clear();
  std::vector<CellEdge> edges = merge(proposals);
  edges.erase(std::remove_if(edges.begin(), edges.end(), [&](const CellEdge& e) { return !is_cell[e.lo] || !is_cell[e.hi]; }),
              edges.end());
  return laplacian_from_edges(std::move(lap.rows), std::move(lap.area), edges);
}

TexelLaplacian with_diffusion_map(const TexelLaplacian& base, const std::vector<float>& factor) {
  // The same cells and faces; the conductances, rates and caches are made anew.
  TexelLaplacian lap = base;
  lap.local.reset();
  lap.backward.reset();
  lap.guard = std::make_shared<std::recursive_mutex>();  // caches of its own
  lap.max_rate = 0;
  for (size_t r = 0; r < base.rows.size(); ++r) {
    const float fi = factor[base.rows[r]];
    double rate = 0;
    for (uint32_t k = base.start[r]; k < base.start[r + 1]; ++k) {
      // The same float expression on both sides of a face: symmetric to the bit.
      const float fj = factor[base.col[k]];
      lap.weight[k] = base.weight[k] * (0.5f * (std::min(fi, fj) + std::max(fi, fj)));
      rate += lap.weight[k];
    }
    lap.rate[r] = static_cast<float>(rate / lap.area[lap.rows[r]]);
    lap.max_rate = std::max(lap.max_rate, rate / lap.area[lap.rows[r]]);
  }
  lap.sorted_rate = lap.rate;
  std::sort(lap.sorted_rate.begin(), lap.sorted_rate.end());
  return lap;
}

namespace {
uint32_t substeps_for(double rate, double rdt) {
  const double x = rate * rdt / kForwardLimit;
  if (!(x > 1.0)) return 1;
  if (x >= 4e9) return UINT32_MAX;
  return static_cast<uint32_t>(std::ceil(x));
}
}  // namespace

uint32_t forward_substeps(const TexelLaplacian& lap, double r_dif, double dt) {
  return local_stepping_plan(lap, r_dif, dt).coarse;
}

const LocalSteppingPlan& local_stepping_plan(const TexelLaplacian& lap, double r_dif, double dt) {
  const auto lock = lap.lock();
  const double rdt = r_dif * dt;
  if (lap.local && lap.local->rdt == rdt) return *lap.local;
  auto plan = std::make_shared<LocalSteppingPlan>();
  plan->rdt = rdt;
  // The coarse sub-step count with the least work: n passes over every cell plus, in
  // each, `fine` passes over the cells too stiff for the coarse sub-step.
  const uint32_t global = substeps_for(lap.max_rate, rdt);
  plan->coarse = global;
  if (global != UINT32_MAX && global > 1 && !lap.sorted_rate.empty()) {
    const double cells = static_cast<double>(lap.sorted_rate.size());
    double best = static_cast<double>(global) * cells;
    // Only counts forward Euler may run are worth weighing (a plan of more than
    // kMaxForwardSubsteps goes to backward Euler or is refused): without this bound a
    // sliver texel (max_rate ~1e12) made this loop run billions of times.
    const uint32_t last = std::min(global, kMaxForwardSubsteps + 1);
    for (uint32_t n = 1; n < last; ++n) {
      const double h = rdt / n;
      const uint32_t fine = substeps_for(lap.max_rate, h);
      if (fine > kMaxFineSubsteps) continue;
      const float limit = static_cast<float>(kForwardLimit / h);
      const double stiff = static_cast<double>(lap.sorted_rate.end() -
                                               std::upper_bound(lap.sorted_rate.begin(), lap.sorted_rate.end(), limit));
      const double cost = n * (cells + kFineCellCost * stiff * fine);
      if (cost < best) {
        best = cost;
        plan->coarse = n;
      }
    }
  }
  const double h = plan->coarse == UINT32_MAX ? 0.0 : rdt / plan->coarse;
  plan->fine = h > 0 ? substeps_for(lap.max_rate, h) : 1;
  if (plan->fine > 1 && plan->coarse != UINT32_MAX) {
    plan->step_class.assign(lap.area.size(), MTX_STEP_COARSE);
    for (size_t r = 0; r < lap.rows.size(); ++r)
      if (lap.rate[r] * h > kForwardLimit) {
        plan->fine_rows.push_back(static_cast<uint32_t>(r));
        plan->step_class[lap.rows[r]] = MTX_STEP_FINE;
      }
    std::vector<uint32_t> fine_index(lap.area.size(), 0);
    for (size_t f = 0; f < plan->fine_rows.size(); ++f) fine_index[lap.rows[plan->fine_rows[f]]] = uint32_t(f);
    plan->fine_start.assign(1, 0);
    plan->link.assign(lap.col.size(), 0);
    for (uint32_t r : plan->fine_rows) {
      plan->fine_cell.push_back(lap.rows[r]);
      plan->fine_area.push_back(lap.area[lap.rows[r]]);
      for (uint32_t k = lap.start[r]; k < lap.start[r + 1]; ++k) {
        const uint32_t j = lap.col[k];
        const uint32_t e = static_cast<uint32_t>(plan->fine_nbr.size());
        if (plan->step_class[j] == MTX_STEP_FINE) {
          plan->fine_nbr.push_back(MTX_FINE_NEIGHBOUR | fine_index[j]);
        } else {
          plan->step_class[j] = MTX_STEP_BORDER;
          plan->fine_nbr.push_back(j);
          plan->link[reverse_entry(lap, r, k)] = e;
        }
        plan->fine_weight.push_back(lap.weight[k]);
      }
      plan->fine_start.push_back(static_cast<uint32_t>(plan->fine_nbr.size()));
    }
  }
  if (plan->fine_rows.empty()) plan->fine = 1;
  lap.local = plan;
  return *plan;
}

bool use_backward_euler(const TexelLaplacian& lap, double r_dif, double dt, uint32_t integrator) {
  const uint32_t substeps = forward_substeps(lap, r_dif, dt);
  const uint32_t fine = substeps == UINT32_MAX ? UINT32_MAX : local_stepping_plan(lap, r_dif, dt).fine;
  const bool too_many = substeps > kMaxForwardSubsteps || fine > kMaxFineSubsteps;
  switch (integrator) {
    case MOLDTEX_INTEGRATOR_AUTO: return substeps > kAutoForwardSubsteps || fine > kMaxFineSubsteps;
    case MOLDTEX_INTEGRATOR_FORWARD:
      if (too_many)
        fail(MOLDTEX_ERROR_INVALID_ARGUMENT,
             "Forward Euler would need " +
                 (substeps == UINT32_MAX ? std::string("billions of") : std::to_string(substeps)) +
                 " sub-steps per step (and " + (fine == UINT32_MAX ? std::string("billions") : std::to_string(fine)) +
                 " finer ones for the smallest texels) to stay stable (at most " +
                 std::to_string(kMaxForwardSubsteps) + " and " + std::to_string(kMaxFineSubsteps) +
                 "): use backward Euler, or a smaller time step or diffusion rate");
      return false;
    case MOLDTEX_INTEGRATOR_BACKWARD: return true;
    default: fail(MOLDTEX_ERROR_INVALID_ARGUMENT, "Unknown integrator " + std::to_string(integrator));
  }
}

PdeStepInfo advance_diffusion_decay(const TexelLaplacian& lap, float* u, std::vector<float>& scratch,
                                    double r_dif, double r_dec, double dt, uint32_t integrator,
                                    ThreadPool& pool) {
  if (!(r_dif >= 0) || !(r_dec >= 0) || !(dt >= 0) || !std::isfinite(r_dif * dt) ||
      !std::isfinite(r_dec * dt))
    fail(MOLDTEX_ERROR_INVALID_ARGUMENT, "Diffusion and decay rates and the time step must be "
                                         "finite and not negative");
  const auto lock = lap.lock();
  const uint32_t substeps = forward_substeps(lap, r_dif, dt);
  const bool backward = use_backward_euler(lap, r_dif, dt, integrator);
  const double decay = std::exp(-r_dec * dt);
  PdeStepInfo info;
  info.backward = backward;
  if (backward)
    info.iterations = backward_step(lap, u, r_dif * dt, decay);
  else {
    info.substeps = substeps;
    forward_steps(lap, local_stepping_plan(lap, r_dif, dt), u, scratch, r_dif * dt / substeps, substeps,
                  decay, pool);
  }
  return info;
}

size_t TexelLaplacian::bytes() const {
  const auto held = lock();
  size_t b = (rows.capacity() + start.capacity() + col.capacity()) * 4 +
             (weight.capacity() + area.capacity() + rate.capacity() + sorted_rate.capacity()) * 4;
  if (local)
    b += (local->fine_rows.capacity() + local->fine_cell.capacity() + local->fine_start.capacity() +
          local->fine_nbr.capacity() + local->link.capacity() + local->fine_area.capacity() +
          local->fine_weight.capacity()) * 4 +
         local->step_class.capacity() +
         (local->cur.capacity() + local->next.capacity() + local->flux.capacity()) * 4;
  if (local && local->lanes) {
    const CoarseLanes& l = *local->lanes;
    b += (l.cell.capacity() + l.first.capacity() + l.col.capacity() + l.lone.capacity() + l.weight.capacity() +
          l.area.capacity() + l.border_lane.capacity() + l.border_start.capacity() + l.border_link.capacity() +
          l.drawn.capacity()) * 4;
  }
  return b;
}

double total_amount(const TexelLaplacian& lap, const float* u) {
  double sum = 0;
  for (uint32_t i : lap.rows) sum += static_cast<double>(lap.area[i]) * u[i];
  return sum;
}

}  // namespace moldtex
