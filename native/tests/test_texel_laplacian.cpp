// The continuous model's diffusion-decay PDE on the texture domain
// (domain/texel_laplacian.h): a finite-volume Laplacian over the island texels that
// measures the surface. White-box: these tests call the core's C++ directly (see
// CMakeLists.txt), because the PDE must be checked on its own, before agents and
// deposits are mixed in.
//
// Every measure is taken in 3D, from the mesh itself (cell centres and areas are
// recomputed here, not read back from the operator under test), and every tolerance says
// where it comes from.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>

#include "common/error.h"
#include "domain/texel_laplacian.h"
#include "domain/texture_domain.h"
#include "shared/pde.h"
#include "surface/surface.h"
#include "test_util.h"

namespace mtx {
namespace {

// A mesh with its surface, texture domain and texel Laplacian.
struct Pde {
  moldtex::Surface surface;
  moldtex::TextureDomain domain;
  moldtex::TexelLaplacian lap;
  std::vector<Vec3> centre;  // 3D position of each cell's texel centre (per texel)

  Pde(const Mesh& m, uint32_t W, uint32_t H, unsigned threads = 2) {
    moldtex::ThreadPool pool(threads);
    surface = moldtex::build_surface(m.desc());
    domain = moldtex::build_texture_domain(surface, W, H, pool);
    lap = moldtex::build_texel_laplacian(surface, domain, pool);
    centre.assign(domain.texel_count(), Vec3{0, 0, 0});
    for (uint32_t i : lap.rows) {
      const uint32_t t = uint32_t(domain.texel_triangle[i]);
      const Vec2 a = m.corner_uv(t, 0), b = m.corner_uv(t, 1), c = m.corner_uv(t, 2);
      const double u = (i % W + 0.5) / W, v = (i / W + 0.5) / H;
      const double det = (b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1]);
      const double l1 = ((u - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (v - a[1])) / det;
      const double l2 = ((b[0] - a[0]) * (v - a[1]) - (u - a[0]) * (b[1] - a[1])) / det;
      centre[i] = add(add(scale(m.corner(t, 0), 1 - l1 - l2), scale(m.corner(t, 1), l1)),
                      scale(m.corner(t, 2), l2));
    }
  }
  size_t texels() const { return domain.texel_count(); }
  uint32_t texel(uint32_t x, uint32_t y) const { return y * domain.width + x; }
  bool is_cell(uint32_t i) const { return lap.area[i] > 0; }

  std::vector<float> random_field(uint64_t seed) const {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<float> uniform(0.f, 1.f);
    std::vector<float> u(texels(), 0.f);
    for (uint32_t i : lap.rows) u[i] = uniform(rng);
    return u;
  }
  // Unit amount in the single cell i.
  std::vector<float> blob(uint32_t i) const {
    std::vector<float> u(texels(), 0.f);
    u[i] = 1.f / lap.area[i];
    return u;
  }
  moldtex::PdeStepInfo advance(std::vector<float>& u, double r_dif, double r_dec, double dt,
                               int steps, uint32_t integrator, unsigned threads = 2) {
    moldtex::ThreadPool pool(threads);
    std::vector<float> scratch;
    moldtex::PdeStepInfo info;
    for (int s = 0; s < steps; ++s)
      info = moldtex::advance_diffusion_decay(lap, u.data(), scratch, r_dif, r_dec, dt, integrator, pool);
    return info;
  }
  double amount(const std::vector<float>& u) const { return moldtex::total_amount(lap, u.data()); }
  // Amount in the cells whose texel satisfies pred(x, y).
  template <class Pred>
  double amount_where(const std::vector<float>& u, Pred pred) const {
    double sum = 0;
    for (uint32_t i : lap.rows)
      if (pred(i % domain.width, i / domain.width)) sum += double(lap.area[i]) * u[i];
    return sum;
  }
  // Amount-weighted mean of (P - origin)[axis]^2 over the cells (the variance along axis
  // about `origin`, with each cell's amount at its centre).
  double variance(const std::vector<float>& u, const Vec3& origin, int axis) const {
    double m0 = 0, m2 = 0;
    for (uint32_t i : lap.rows) {
      const double w = double(lap.area[i]) * u[i], d = centre[i][axis] - origin[axis];
      m0 += w;
      m2 += w * d * d;
    }
    return m2 / m0;
  }
};

// Every cell's rate sum_j c_ij / A_i.
std::vector<double> cell_rates(const moldtex::TexelLaplacian& lap) {
  std::vector<double> rates;
  for (size_t r = 0; r < lap.rows.size(); ++r) {
    double sum = 0;
    for (uint32_t k = lap.start[r]; k < lap.start[r + 1]; ++k) sum += lap.weight[k];
    rates.push_back(sum / lap.area[lap.rows[r]]);
  }
  return rates;
}

const uint32_t kForward = MOLDTEX_INTEGRATOR_FORWARD, kBackward = MOLDTEX_INTEGRATOR_BACKWARD,
               kAuto = MOLDTEX_INTEGRATOR_AUTO;

Mesh UnitPlane(std::function<Vec2(double, double)> uv = [](double x, double y) { return Vec2{x, y}; }) {
  return make_plane(32, 32, 0, 0, 1, 1, uv);
}

// On a plane with square texels of side h the operator is the standard 5-point
// Laplacian: area h^2, conductance 1 to each of the 4 grid neighbours (fewer at the
// plane's open border: no faces there). Float rounding of h^2 and of c only.
TEST(TexelLaplacian, RegularPlaneIsTheFivePointLaplacian) {
  const uint32_t W = 64;
  Pde p(UnitPlane(), W, W);
  ASSERT_EQ(p.lap.rows.size(), size_t(W) * W);
  const double h = 1.0 / W;
  for (size_t r = 0; r < p.lap.rows.size(); ++r) {
    const uint32_t i = p.lap.rows[r], x = i % W, y = i / W;
    EXPECT_NEAR(p.lap.area[i], h * h, 1e-6 * h * h) << "texel " << x << "," << y;
    const uint32_t expected = (x > 0) + (x + 1 < W) + (y > 0) + (y + 1 < W);
    ASSERT_EQ(p.lap.start[r + 1] - p.lap.start[r], expected) << "texel " << x << "," << y;
    for (uint32_t k = p.lap.start[r]; k < p.lap.start[r + 1]; ++k) {
      const uint32_t j = p.lap.col[k];
      EXPECT_EQ(std::abs(int(j % W) - int(x)) + std::abs(int(j / W) - int(y)), 1);
      EXPECT_NEAR(p.lap.weight[k], 1.0, 1e-5);
    }
  }
  EXPECT_NEAR(p.lap.max_rate, 4.0 / (h * h), 1e-5 * 4.0 / (h * h));
  EXPECT_NEAR(p.lap.total_area, 1.0, 1e-6);
}

// The operator is symmetric entry by entry (the same float for (i, j) and (j, i)),
// which is what makes the amount conserved: on a mesh with seams everywhere.
TEST(TexelLaplacian, SymmetricWithSeams) {
  for (const Mesh& m : {make_uv_sphere(32, 16, 1.0), make_torus(32, 16, 1.0, 0.4), make_cube()}) {
    Pde p(m, 128, 128);
    size_t seam_edges = 0;
    for (size_t r = 0; r < p.lap.rows.size(); ++r) {
      const uint32_t i = p.lap.rows[r];
      for (uint32_t k = p.lap.start[r]; k < p.lap.start[r + 1]; ++k) {
        const uint32_t j = p.lap.col[k];
        ASSERT_TRUE(p.is_cell(j));
        ASSERT_NE(i, j);
        ASSERT_GT(p.lap.weight[k], 0.f);
        const size_t rj = std::lower_bound(p.lap.rows.begin(), p.lap.rows.end(), j) - p.lap.rows.begin();
        const auto begin = p.lap.col.begin() + p.lap.start[rj], end = p.lap.col.begin() + p.lap.start[rj + 1];
        const auto back = std::find(begin, end, i);
        ASSERT_NE(back, end) << i << " -> " << j << " has no way back";
        EXPECT_EQ(p.lap.weight[back - p.lap.col.begin()], p.lap.weight[k]);
        const int dx = std::abs(int(i % 128) - int(j % 128)), dy = std::abs(int(i / 128) - int(j / 128));
        seam_edges += dx + dy != 1;
      }
    }
    EXPECT_GT(seam_edges, 0u) << "no edge across a seam";
  }
}

// 1. Mass conservation with r_dec = 0, random start, on meshes whose seams the operator
// must bridge (the UV sphere's meridian and poles, the torus' texture border).
// Forward: the operator conserves exactly in real arithmetic (symmetric to the bit, flux
// form); what remains is the rounding of each stored value, at most half an ulp
// (2^-25 of its amount) per cell and sub-step: 1.8e-4 relative over these 3000 sub-steps
// if all roundings had the same sign, 1e-8 if their signs were random. Neither holds:
// once the field is nearly uniform, fluxes below half an ulp round away in large cells
// and up to an ulp in small ones, a steady bias of ~3e-9 per step (measured: drift 1e-8
// over the first 300 steps, then ~3e-6 at 1000). 1e-5 leaves 3x over that and catches
// any leak of the operator itself: a 1e-6 asymmetry in one weight moves 1e-6 of the flux
// through it every sub-step.
// Backward: each CG solve leaves a residual r with |r| <= 1e-6 |M u|, and the amount
// changes by sum_i r_i (1^T K = 0): at most ~1e-6 per step if every residual had the same
// sign, 1e-4 over 100 steps; measured ~2e-6, so the same 1e-5.
TEST(TexelLaplacian, ConservesTheAmountAcrossSeams) {
  struct Case {
    const char* name;
    Mesh mesh;
  };
  for (const Case& c : {Case{"sphere", make_uv_sphere(32, 16, 1.0)}, Case{"torus", make_torus(32, 16, 1.0, 0.4)}}) {
    SCOPED_TRACE(c.name);
    Pde p(c.mesh, 128, 128);
    // 3 sub-steps per step for the stiffest cell: on the sphere that is local time
    // stepping (its pole cells fine), on the torus global sub-steps; both must conserve.
    const double dt = 0.01, r_dif = 2.0 / (p.lap.max_rate * dt);
    std::vector<float> u = p.random_field(7);
    const double before = p.amount(u);
    const auto info = p.advance(u, r_dif, 0.0, dt, 1000, kForward);
    const moldtex::LocalSteppingPlan& plan = moldtex::local_stepping_plan(p.lap, r_dif, dt);
    EXPECT_EQ(info.substeps, moldtex::forward_substeps(p.lap, r_dif, dt));
    EXPECT_EQ(plan.coarse * plan.fine >= 3, true) << "the stiffest cell still takes >= 3 sub-steps";
    std::printf("[ %s ] %u coarse x %u fine sub-steps, %zu fine cells\n", c.name, plan.coarse, plan.fine,
                plan.fine_rows.size());
    const double forward_drift = std::fabs(p.amount(u) / before - 1);
    EXPECT_LT(forward_drift, 1e-5);

    std::vector<float> v = p.random_field(7);
    const auto binfo = p.advance(v, 100 * r_dif, 0.0, dt, 100, kBackward);
    EXPECT_TRUE(binfo.backward);
    const double backward_drift = std::fabs(p.amount(v) / before - 1);
    EXPECT_LT(backward_drift, 1e-5);
    std::printf("[ %s ] cells %zu, forward drift %.2e after 1000 steps (%u sub-steps each), "
                "backward drift %.2e after 100 steps (%u CG iterations on the last)\n",
                c.name, p.lap.rows.size(), forward_drift, info.substeps, backward_drift, binfo.iterations);
  }
}

// 2. Pure decay (r_dif = 0): u = u0 exp(-r_dec t). Each step multiplies by the float
// exp(-r_dec dt) (one rounding) and rounds the product (one more): at most 2 * 2^-24
// relative per step, 50 steps -> 6e-6.
TEST(TexelLaplacian, PureDecayIsExact) {
  Pde p(make_torus(32, 16, 1.0, 0.4), 64, 64);
  const std::vector<float> u0 = p.random_field(3);
  const double r_dec = 2.0, dt = 0.1;
  const int steps = 50;
  for (uint32_t integrator : {kForward, kBackward}) {
    std::vector<float> u = u0;
    p.advance(u, 0.0, r_dec, dt, steps, integrator);
    double worst = 0;
    for (uint32_t i : p.lap.rows) {
      const double expected = u0[i] * std::exp(-r_dec * dt * steps);
      worst = std::max(worst, std::fabs(u[i] - expected) / expected);
    }
    EXPECT_LT(worst, 2.0 * steps * std::ldexp(1.0, -24)) << "integrator " << integrator;
  }
}

// 3a. A one-texel blob on a plane with square texels spreads with variance 2 r_dif t per
// axis, measured in 3D. The variance is taken with each cell's amount at its centre, so
// the blob starts at 0 (as a uniform texel it would be h^2/12 = 1.3e-6, 0.02% of the
// final 0.006). On a regular grid the 5-point scheme grows this second moment by exactly
// 2 r_dif dt per step for both integrators as long as nothing reaches the border: the
// blob ends with sigma = 0.077, 6.5 sigma from the border. So the 5% the model allows is
// wide; 1% still catches any error in conductances or areas (a factor, not a rounding).
TEST(TexelLaplacian, BlobSpreadsWithTheDiffusionRate) {
  const uint32_t W = 256;
  Pde p(UnitPlane(), W, W);
  const uint32_t centre = p.texel(W / 2, W / 2);
  const double r_dif = 0.01, dt = 0.01;
  const int steps = 30;  // r_dif t = 0.003
  const double expected = 2 * r_dif * dt * steps;
  for (uint32_t integrator : {kForward, kBackward}) {
    std::vector<float> u = p.blob(centre);
    p.advance(u, r_dif, 0.0, dt, steps, integrator);
    for (int axis = 0; axis < 2; ++axis) {
      const double ratio = p.variance(u, p.centre[centre], axis) / expected;
      EXPECT_NEAR(ratio, 1.0, 0.01) << "integrator " << integrator << " axis " << axis;
      std::printf("[ plane ] %s, axis %d: variance / (2 r t) = %.6f\n",
                  integrator == kForward ? "forward" : "backward", axis, ratio);
    }
    EXPECT_NEAR(p.variance(u, p.centre[centre], 2), 0.0, 1e-12);
  }
}

// 3b. The same on a plane whose UVs are warped u = x^2: texels at x = 0.3 are 2.7x wider
// in 3D than at x = 0.8 (and 1.7x wider than tall there; 0.6x at x = 0.8). Spread
// measured in 3D must not care: both blobs reach the same variance within 10%, each
// within 5% of 2 r_dif t. sigma = 0.05 leaves 6 sigma to the border on the stretched
// side, 4 sigma on the compressed side (3e-5 of the amount beyond: negligible).
TEST(TexelLaplacian, SpreadIsTheSameOnStretchedAndCompressedTexels) {
  const uint32_t W = 256;
  Pde p(UnitPlane([](double x, double y) { return Vec2{x * x, y}; }), W, W);
  const double r_dif = 0.01, dt = 0.005;
  const int steps = 25;  // r_dif t = 0.00125
  const double expected = 2 * r_dif * dt * steps;
  double spread[2][2];
  const double xs[2] = {0.3, 0.8};
  for (int b = 0; b < 2; ++b) {
    const uint32_t i = p.texel(uint32_t(xs[b] * xs[b] * W), W / 2);
    const double width = 1.0 / (2 * xs[b] * W);
    EXPECT_NEAR(p.centre[i][0], xs[b], width);
    std::vector<float> u = p.blob(i);
    const auto info = p.advance(u, r_dif, 0.0, dt, steps, kForward);
    for (int axis = 0; axis < 2; ++axis) {
      spread[b][axis] = p.variance(u, p.centre[i], axis);
      EXPECT_NEAR(spread[b][axis] / expected, 1.0, 0.05) << "x " << xs[b] << " axis " << axis;
    }
    std::printf("[ warped ] blob at x %.1f (texel %.4f x %.4f): variance / (2 r t) = %.4f, %.4f "
                "(%u sub-steps)\n",
                xs[b], width, 1.0 / W, spread[b][0] / expected, spread[b][1] / expected, info.substeps);
  }
  for (int axis = 0; axis < 2; ++axis)
    EXPECT_NEAR(spread[0][axis] / spread[1][axis], 1.0, 0.1) << "axis " << axis;
}

// 4. Across the torus' texture-border seams: a one-texel blob in column 0 (row 0) must
// spread the same way across the seam (to columns W-1, W-2, ...; rows H-1, ...) as
// away from it (columns 1, 2, ...), since the torus is symmetric about the blob's
// meridian (circle of latitude) up to the mesh's 48 x 24 facets. Without the seam edges
// the far side would get nothing. 10%: the facets and the half-texel offset of the blob
// from the z = 0 plane are the only asymmetry; measured below.
TEST(TexelLaplacian, DiffusesSymmetricallyAcrossTheTextureBorderSeam) {
  const uint32_t W = 192, H = 96;
  Pde p(make_torus(48, 24, 1.0, 0.4), W, H);
  ASSERT_EQ(p.lap.rows.size(), size_t(W) * H);
  const double r_dif = 0.01, dt = 0.05;
  const int steps = 17;  // sigma ~ 0.13: 4 texels along u, 5 along v
  struct Case {
    const char* name;
    uint32_t x, y;
    bool along_u;
  };
  for (const Case& c : {Case{"u seam", 0, H / 4, true}, Case{"v seam", W / 2, 0, false}}) {
    std::vector<float> u = p.blob(p.texel(c.x, c.y));
    const double before = p.amount(u);
    p.advance(u, r_dif, 0.0, dt, steps, kAuto);
    EXPECT_NEAR(p.amount(u) / before, 1.0, 1e-5) << c.name;
    const uint32_t n = c.along_u ? W : H, reach = n / 4;
    auto offset = [&](uint32_t x, uint32_t y) { return c.along_u ? x : y; };
    const double near = p.amount_where(u, [&](uint32_t x, uint32_t y) {
      const uint32_t o = offset(x, y);
      return o >= 1 && o <= reach;
    });
    const double across = p.amount_where(u, [&](uint32_t x, uint32_t y) {
      const uint32_t o = offset(x, y);
      return o >= n - reach;
    });
    std::printf("[ torus ] %s: amount on the blob's side %.4f, across the seam %.4f (ratio %.4f)\n",
                c.name, near, across, across / near);
    EXPECT_GT(near, 0.2 * before) << c.name;
    EXPECT_NEAR(across / near, 1.0, 0.1) << c.name;
  }
}

// 5a. Forward and backward Euler agree for a small dt. On a smooth field (one period
// around each circle of the torus) both approximate the same ODE; their difference is
// the time-discretisation error, about t dt (r_dif lambda)^2 / 2 on the field's varying
// part: lambda ~ 1 / R^2 + 1 / r^2 = 7, r_dif lambda = 0.35, t = 0.8, dt = 0.002 ->
// 1e-4 of the amplitude 0.5, 4e-5 of |u| (measured 5e-5). Bound 2e-4. A wrong factor in
// either integrator shows at the scale of what diffusion changes over the run (6%).
TEST(TexelLaplacian, ForwardAndBackwardAgreeForSmallSteps) {
  const uint32_t W = 192, H = 96;
  Pde p(make_torus(48, 24, 1.0, 0.4), W, H);
  std::vector<float> u0(p.texels(), 0.f);
  for (uint32_t i : p.lap.rows) {
    const double s = (i % W + 0.5) / W, t = (i / W + 0.5) / H;
    u0[i] = float(1 + 0.5 * std::cos(2 * kPi * s) * std::sin(2 * kPi * t));
  }
  const double dt = 0.002, r_dif = 0.8 / (p.lap.max_rate * dt);  // one sub-step
  const int steps = 400;
  std::vector<float> f = u0, b = u0;
  EXPECT_EQ(p.advance(f, r_dif, 0.5, dt, steps, kForward).substeps, 1u);
  EXPECT_TRUE(p.advance(b, r_dif, 0.5, dt, steps, kBackward).backward);
  double diff = 0, norm = 0, change = 0;
  for (uint32_t i : p.lap.rows) {
    diff += double(f[i] - b[i]) * (f[i] - b[i]);
    norm += double(f[i]) * f[i];
    const double undiffused = u0[i] * std::exp(-0.5 * dt * steps);
    change += (f[i] - undiffused) * (f[i] - undiffused);
  }
  const double relative = std::sqrt(diff / norm), moved = std::sqrt(change / norm);
  std::printf("[ torus ] forward vs backward, r_dif %.4f, %d steps of %.3f: relative L2 "
              "difference %.2e (diffusion changed the field by %.2e)\n",
              r_dif, steps, dt, relative, moved);
  EXPECT_GT(moved, 0.05);
  EXPECT_LT(relative, 2e-4);
}

// 5a'. Local time stepping where it matters: the UV sphere, whose pole cells are up to
// 25x stiffer than the median. Forward Euler with fine sub-steps for those cells against
// backward Euler at a tenth of the step. The difference is forward Euler's own error
// where cells step close to their stability limit (h * rate up to 0.9: the 1% stiffest
// cells, as the stiffest cell does under global sub-steps): measured 1.1e-3 relative L2
// and 0.7% in the worst cell (5 coarse x 9 fine sub-steps, 14% of the cells fine, against
// 45 global ones), where diffusion changed the field by 14%; bounds about 3x that.
// A smooth field of the 3D position, so the comparison measures the integrators.
TEST(TexelLaplacian, LocalTimeSteppingAgreesWithBackwardEuler) {
  const Mesh m = make_uv_sphere(64, 32, 1.0);
  Pde p(m, 256, 256);
  std::vector<float> u0(p.texels(), 0.f);
  for (uint32_t i : p.lap.rows) {
    const double s = (i % 256 + 0.5) / 256, t = (i / 256 + 0.5) / 256;
    const Vec3 x = {std::sin(kPi * t) * std::cos(2 * kPi * s), std::sin(kPi * t) * std::sin(2 * kPi * s), std::cos(kPi * t)};
    u0[i] = float(1 + 0.5 * std::cos(6 * x[0]) * std::sin(5 * x[1] + 4 * x[2]));
  }
  const double dt = 0.002, r_dif = 40.0 / (p.lap.max_rate * dt);  // 45 global sub-steps
  const moldtex::LocalSteppingPlan plan = moldtex::local_stepping_plan(p.lap, r_dif, dt);
  ASSERT_FALSE(plan.fine_rows.empty());
  const int steps = 200;
  std::vector<float> f = u0, b = u0;
  p.advance(f, r_dif, 0.5, dt, steps, kForward);
  // The reference: backward Euler at a tenth of the step (its own error 10x smaller).
  p.advance(b, r_dif, 0.5, dt / 10, steps * 10, kBackward);
  double diff = 0, norm = 0, change = 0, worst = 0;
  for (uint32_t i : p.lap.rows) {
    diff += double(f[i] - b[i]) * (f[i] - b[i]);
    norm += double(f[i]) * f[i];
    const double undiffused = u0[i] * std::exp(-0.5 * dt * steps);
    change += (f[i] - undiffused) * (f[i] - undiffused);
    worst = std::max(worst, double(std::fabs(f[i] - b[i])) / f[i]);
  }
  const double relative = std::sqrt(diff / norm), moved = std::sqrt(change / norm);
  std::printf("[ sphere ] %u coarse x %u fine sub-steps (%zu fine cells of %zu): local vs backward "
              "relative L2 %.2e, worst cell %.2e (diffusion changed the field by %.2e)\n",
              plan.coarse, plan.fine, plan.fine_rows.size(), p.lap.rows.size(), relative, worst, moved);
  EXPECT_GT(moved, 0.05);
  EXPECT_LT(plan.coarse * 4, 45u) << "local time stepping must save most of the global sub-steps";
  EXPECT_LT(relative, 3e-3);
  EXPECT_LT(worst, 2e-2);
}

// 5a'. Local time stepping keeps the fine cells' rows, values and inflows in compact
// tables (LocalSteppingPlan) for speed. The tables must describe the same operator as the
// matrix: each fine cell's compact row is its CSR row (same neighbours, same conductances,
// same order), each border cell's link leads to the compact entry of the same face seen
// from the fine side, and border cells are exactly the coarse cells with a fine
// neighbour. And the result must be the one the matrix read in place gives, bit for bit:
// the reference below is that in-place algorithm (the one before the compact tables), so
// a wrong link or a reordered sum shows up as differing bits, which no tolerance hides.
TEST(TexelLaplacian, LocalSteppingTablesAreTheMatrixBitForBit) {
  const Mesh m = make_uv_sphere(64, 32, 1.0);
  Pde p(m, 256, 256);
  const moldtex::TexelLaplacian& lap = p.lap;
  const double dt = 0.002, r_dif = 40.0 / (lap.max_rate * dt);
  const moldtex::LocalSteppingPlan& plan = moldtex::local_stepping_plan(lap, r_dif, dt);
  ASSERT_FALSE(plan.fine_rows.empty());
  ASSERT_EQ(plan.fine_cell.size(), plan.fine_rows.size());
  std::vector<uint32_t> row_of(p.texels(), UINT32_MAX);
  for (size_t r = 0; r < lap.rows.size(); ++r) row_of[lap.rows[r]] = uint32_t(r);
  const auto is_fine = [&](uint32_t i) { return plan.step_class[i] == MTX_STEP_FINE; };
  size_t links = 0;
  for (size_t f = 0; f < plan.fine_rows.size(); ++f) {
    const uint32_t r = plan.fine_rows[f], i = lap.rows[r];
    ASSERT_EQ(plan.fine_cell[f], i);
    ASSERT_EQ(plan.fine_area[f], lap.area[i]);
    ASSERT_EQ(plan.fine_start[f + 1] - plan.fine_start[f], lap.start[r + 1] - lap.start[r]);
    for (uint32_t k = lap.start[r], e = plan.fine_start[f]; k < lap.start[r + 1]; ++k, ++e) {
      const uint32_t j = lap.col[k], n = plan.fine_nbr[e];
      ASSERT_EQ(plan.fine_weight[e], lap.weight[k]);
      if (is_fine(j)) {
        ASSERT_NE(n & MTX_FINE_NEIGHBOUR, 0u);
        ASSERT_EQ(plan.fine_cell[n & ~MTX_FINE_NEIGHBOUR], j);
      } else {
        ASSERT_EQ(n, j);
        ASSERT_EQ(plan.step_class[j], MTX_STEP_BORDER);
        ASSERT_EQ(plan.link[moldtex::reverse_entry(lap, r, k)], e) << "the border cell's entry back must lead here";
        ++links;
      }
    }
  }
  size_t border = 0;
  for (size_t r = 0; r < lap.rows.size(); ++r) {
    const uint32_t i = lap.rows[r];
    bool fine_neighbour = false;
    for (uint32_t k = lap.start[r]; k < lap.start[r + 1]; ++k) fine_neighbour |= is_fine(lap.col[k]);
    if (!is_fine(i)) {
      EXPECT_EQ(plan.step_class[i] == MTX_STEP_BORDER, fine_neighbour) << "cell " << i;
    }
    border += plan.step_class[i] == MTX_STEP_BORDER;
  }

  // Three steps of the in-place algorithm against advance_diffusion_decay.
  std::vector<float> u = p.random_field(11), ref = u;
  const uint32_t n = plan.coarse;
  const double h = r_dif * dt / n;
  const float hf = float(h), hfine = float(h / plan.fine), decay = float(std::exp(-0.5 * dt));
  std::vector<float> out(ref.size()), cur(ref.size()), next(ref.size()), flux(lap.col.size());
  for (int step = 0; step < 3; ++step)
    for (uint32_t sub = 0; sub < n; ++sub) {
      const float d = sub + 1 == n ? decay : 1.f;
      for (uint32_t r : plan.fine_rows) cur[lap.rows[r]] = ref[lap.rows[r]];
      std::fill(flux.begin(), flux.end(), 0.f);
      for (uint32_t q = 0; q < plan.fine; ++q) {
        for (uint32_t r : plan.fine_rows) {
          const uint32_t i = lap.rows[r];
          const float ui = cur[i];
          float total = 0.f;
          for (uint32_t k = lap.start[r]; k < lap.start[r + 1]; ++k) {
            const uint32_t j = lap.col[k];
            const float q_k = lap.weight[k] * ((is_fine(j) ? cur[j] : ref[j]) - ui);
            total += q_k;
            if (!is_fine(j)) flux[k] += hfine * q_k;
          }
          next[i] = ui + hfine / lap.area[i] * total;
        }
        for (uint32_t r : plan.fine_rows) cur[lap.rows[r]] = next[lap.rows[r]];
      }
      for (size_t r = 0; r < lap.rows.size(); ++r) {
        const uint32_t i = lap.rows[r];
        if (is_fine(i)) {
          out[i] = cur[i] * d;
          continue;
        }
        const float ui = ref[i];
        float total = 0.f, drawn = 0.f;
        for (uint32_t k = lap.start[r]; k < lap.start[r + 1]; ++k) {
          const uint32_t j = lap.col[k];
          if (is_fine(j))
            drawn += flux[moldtex::reverse_entry(lap, uint32_t(r), k)];
          else
            total += lap.weight[k] * (ref[j] - ui);
        }
        out[i] = (ui + (hf * total - drawn) / lap.area[i]) * d;
      }
      for (uint32_t i : lap.rows) ref[i] = out[i];
    }
  p.advance(u, r_dif, 0.5, dt, 3, kForward);
  size_t differ = 0;
  for (uint32_t i : lap.rows) differ += std::memcmp(&u[i], &ref[i], sizeof(float)) != 0;
  std::printf("[ sphere ] %zu fine cells, %zu border cells, %zu links; %zu of %zu cells differ from the "
              "in-place reference after 3 steps of %u x %u sub-steps\n",
              plan.fine_rows.size(), border, links, differ, lap.rows.size(), n, plan.fine);
  EXPECT_EQ(differ, 0u);
}

// 5a'. The CPU steps the cells that are not fine in lanes of four (CoarseLanes): every such
// cell is in exactly one lane or stepped alone; a lane holds its row's entries in the
// row's order, less those towards fine cells, then padding (its own cell, conductance 0);
// a border cell's fine inflows are listed in its row's order. With global sub-steps (a
// torus and a plane, every cell alike) the lanes give the one-row code's result
// (mtx_diffuse_cell) bit for bit; with local time stepping the test above compares them
// with the in-place algorithm. Checked against a planted fault: lanes that read one slot
// more (the next chunk's first) made every cell differ on the torus and the plane.
TEST(TexelLaplacian, CoarseLanesAreTheMatrixBitForBit) {
  struct Case {
    const char* name;
    Mesh mesh;
    uint32_t side;
    double rate_steps;  // r_dif dt max_rate
  };
  // The plane's rim cells have fewer neighbours, so its lanes are padded.
  for (const Case& c : {Case{"torus", make_torus(32, 16, 1.0, 0.4), 128, 4.0}, Case{"plane", UnitPlane(), 128, 4.0},
                        Case{"sphere", make_uv_sphere(64, 32, 1.0), 256, 40.0}}) {
    Pde p(c.mesh, c.side, c.side);
    const moldtex::TexelLaplacian& lap = p.lap;
    const double dt = 0.002, r_dif = c.rate_steps / (lap.max_rate * dt);
    std::vector<float> u = p.random_field(5), ref = u;
    p.advance(u, r_dif, 0.5, dt, 3, kForward);
    const moldtex::LocalSteppingPlan& plan = moldtex::local_stepping_plan(lap, r_dif, dt);
    ASSERT_TRUE(plan.lanes) << c.name;
    const moldtex::CoarseLanes& lanes = *plan.lanes;
    const bool local = !plan.fine_rows.empty();
    const auto is_fine = [&](uint32_t i) { return local && plan.step_class[i] == MTX_STEP_FINE; };
    std::vector<uint32_t> row_of(p.texels(), UINT32_MAX);
    for (size_t r = 0; r < lap.rows.size(); ++r) row_of[lap.rows[r]] = uint32_t(r);
    std::vector<int> seen(p.texels(), 0);
    ASSERT_EQ(lanes.cell.size(), 4 * lanes.chunks());
    ASSERT_LT(lanes.lone.size(), 4u);
    size_t border = 0;
    for (size_t c4 = 0; c4 < lanes.chunks(); ++c4)
      for (uint32_t l = 0; l < 4; ++l) {
        const uint32_t lane = uint32_t(4 * c4 + l), i = lanes.cell[lane], r = row_of[i];
        ++seen[i];
        ASSERT_EQ(lanes.area[lane], lap.area[i]);
        std::vector<uint32_t> cols, links;
        std::vector<float> weights;
        for (uint32_t k = lap.start[r]; k < lap.start[r + 1]; ++k) {
          if (is_fine(lap.col[k])) {
            links.push_back(plan.link[k]);
            continue;
          }
          cols.push_back(lap.col[k]);
          weights.push_back(lap.weight[k]);
        }
        const uint32_t slots = lanes.first[c4 + 1] - lanes.first[c4];
        ASSERT_GE(slots, cols.size());
        for (uint32_t s = 0; s < slots; ++s) {
          const uint32_t at = 4 * (lanes.first[c4] + s) + l;
          ASSERT_EQ(lanes.col[at], s < cols.size() ? cols[s] : i) << c.name << " cell " << i << " slot " << s;
          ASSERT_EQ(lanes.weight[at], s < cols.size() ? weights[s] : 0.f) << c.name << " cell " << i;
        }
        if (links.empty()) continue;
        ASSERT_LT(border, lanes.border_lane.size());
        ASSERT_EQ(lanes.border_lane[border], lane);
        ASSERT_EQ(std::vector<uint32_t>(lanes.border_link.begin() + lanes.border_start[border],
                                        lanes.border_link.begin() + lanes.border_start[border + 1]),
                  links);
        ++border;
      }
    EXPECT_EQ(border, lanes.border_lane.size());
    for (uint32_t r : lanes.lone) ++seen[lap.rows[r]];
    size_t fine = 0;
    for (uint32_t i : lap.rows) {
      fine += is_fine(i);
      ASSERT_EQ(seen[i], is_fine(i) ? 0 : 1) << c.name << " cell " << i;
    }
    std::printf("[ %s ] %zu cells: %zu chunks of 4, %zu alone, %zu fine, %zu border; %zu slots for %zu entries\n",
                c.name, lap.rows.size(), lanes.chunks(), lanes.lone.size(), fine, lanes.border_lane.size(),
                lanes.col.size(), lap.col.size());
    if (local) {
      EXPECT_STREQ(c.name, "sphere");
      continue;
    }
    // Global sub-steps: the one-row code, 3 steps.
    const uint32_t n = plan.coarse;
    ASSERT_GT(n, 1u);
    const float hf = float(r_dif * dt / n), decay = float(std::exp(-0.5 * dt));
    std::vector<float> out(ref.size());
    for (int step = 0; step < 3; ++step)
      for (uint32_t sub = 0; sub < n; ++sub) {
        for (size_t r = 0; r < lap.rows.size(); ++r)
          out[lap.rows[r]] = moldtex::mtx_diffuse_cell(lap.rows.data(), lap.start.data(), lap.col.data(), lap.weight.data(),
                                              lap.area.data(), ref.data(), uint32_t(r), hf,
                                              sub + 1 == n ? decay : 1.f);
        for (uint32_t i : lap.rows) ref[i] = out[i];
      }
    size_t differ = 0;
    for (uint32_t i : lap.rows) differ += std::memcmp(&u[i], &ref[i], sizeof(float)) != 0;
    std::printf("[ %s ] %u global sub-steps a step: %zu of %zu cells differ from the one-row code after 3 steps\n",
                c.name, n, differ, lap.rows.size());
    EXPECT_EQ(differ, 0u);
  }
}

// 5b. A step that forward Euler would need more than 256 sub-steps for: FORWARD refuses
// it with a message naming the way out, AUTO and BACKWARD take it. Backward Euler's
// matrix is an M-matrix, so each step is a weighted average: no value leaves the range
// of the start (up to the CG tolerance, 1e-6 of |M u|, so 1e-5 absolute here is ample),
// the 3D-weighted energy sum A u^2 never grows, and the amount is kept.
TEST(TexelLaplacian, BackwardIsStableWhereForwardRefuses) {
  Pde p(make_torus(32, 16, 1.0, 0.4), 128, 128);
  const double dt = 1.0, r_dif = 300 * 0.9 / p.lap.max_rate;
  ASSERT_GT(moldtex::forward_substeps(p.lap, r_dif, dt), 256u);
  std::vector<float> u = p.random_field(11);
  moldtex::ThreadPool pool(2);
  std::vector<float> scratch;
  try {
    moldtex::advance_diffusion_decay(p.lap, u.data(), scratch, r_dif, 0.0, dt, kForward, pool);
    ADD_FAILURE() << "forward Euler took a step it cannot take stably";
  } catch (const moldtex::Error& e) {
    EXPECT_EQ(e.status(), MOLDTEX_ERROR_INVALID_ARGUMENT);
    EXPECT_NE(std::string(e.what()).find("backward Euler"), std::string::npos) << e.what();
  }
  const double before = p.amount(u);
  auto energy = [&](const std::vector<float>& v) {
    double e = 0;
    for (uint32_t i : p.lap.rows) e += double(p.lap.area[i]) * v[i] * v[i];
    return e;
  };
  double last = energy(u);
  for (int step = 0; step < 10; ++step) {
    const auto info = p.advance(u, r_dif, 0.0, dt, 1, step % 2 ? kAuto : kBackward);
    EXPECT_TRUE(info.backward);
    EXPECT_GT(info.iterations, 0u);
    for (uint32_t i : p.lap.rows) {
      ASSERT_GE(u[i], -1e-5f);
      ASSERT_LE(u[i], 1.f + 1e-5f);
    }
    const double e = energy(u);
    EXPECT_LE(e, last * (1 + 1e-6));
    last = e;
  }
  EXPECT_NEAR(p.amount(u) / before, 1.0, 1e-5);
}

// AUTO: forward Euler up to 64 sub-steps (where it is still faster than conjugate gradients), backward beyond.
TEST(TexelLaplacian, AutoSwitchesAtSixtyFourSubsteps) {
  Pde p(make_torus(32, 16, 1.0, 0.4), 64, 64);
  const double dt = 0.01;
  std::vector<float> u = p.random_field(5);
  const double at64 = 64 * 0.9 / (p.lap.max_rate * dt) * 0.999, at65 = 64.5 * 0.9 / (p.lap.max_rate * dt);
  EXPECT_EQ(moldtex::forward_substeps(p.lap, at64, dt), 64u);
  EXPECT_EQ(moldtex::forward_substeps(p.lap, at65, dt), 65u);
  auto info = p.advance(u, at64, 0.0, dt, 1, kAuto);
  EXPECT_FALSE(info.backward);
  EXPECT_EQ(info.substeps, 64u);
  info = p.advance(u, at65, 0.0, dt, 1, kAuto);
  EXPECT_TRUE(info.backward);
  EXPECT_EQ(info.substeps, 0u);
  EXPECT_EQ(moldtex::forward_substeps(p.lap, 0.0, dt), 1u);
}

// 6. Bit-identical for 1, 2 and 4 threads: the operator and both integrators.
TEST(TexelLaplacian, BitIdenticalForAnyThreadCount) {
  const Mesh m = make_uv_sphere(32, 16, 1.0);
  std::vector<float> reference[2];
  moldtex::TexelLaplacian first;
  for (unsigned threads : {1u, 2u, 4u}) {
    Pde p(m, 128, 128, threads);
    if (threads == 1) first = p.lap;
    EXPECT_EQ(p.lap.col, first.col);
    EXPECT_EQ(p.lap.start, first.start);
    EXPECT_EQ(0, std::memcmp(p.lap.weight.data(), first.weight.data(), 4 * first.weight.size()));
    const double dt = 0.01, r_dif = 5.0 / (p.lap.max_rate * dt);
    for (int k = 0; k < 2; ++k) {
      std::vector<float> u = p.random_field(9);
      const auto info = p.advance(u, r_dif * (k ? 10 : 1), 0.3, dt, 20, k ? kBackward : kForward, threads);
      if (!k) {
        EXPECT_EQ(info.substeps, moldtex::forward_substeps(p.lap, r_dif, dt));
        EXPECT_FALSE(moldtex::local_stepping_plan(p.lap, r_dif, dt).fine_rows.empty())
            << "the sphere's poles take local time steps here";
      }
      if (threads == 1)
        reference[k] = u;
      else
        EXPECT_EQ(0, std::memcmp(u.data(), reference[k].data(), 4 * u.size()))
            << threads << " threads, " << (k ? "backward" : "forward");
    }
  }
}

// 7. The UV sphere at 512^2: how much its poles raise the forward sub-step count. A cell's
// rate sum_j c_ij / A_i is about 2 (1 / w^2 + 1 / h^2) for a w x h texel in 3D. Lat-long
// texels narrow as sin(angle from the pole): at the equator 0.0123 x 0.0061 (the median
// cell), 2.5x stiffer 20 degrees from a pole, 4x at 15 degrees (the triangles' chords
// set the width: the top chord of a ring's cells, narrower than the centre). The pole
// fans are narrowest, their width set by the first ring: 64 x 32 mesh 0.0012 (18x the
// median), 32 x 16 mesh 0.0024 (5x); some fan texels also get a one-sided seam edge
// across the fans' sawtooth (up to 1.4x more). So every cell more than 4x stiffer than
// the median must lie within 25 degrees of a pole, and the largest rate must stay below
// 30x the median (18 x 1.4 = 25). A stiff edge anywhere else (a seam edge with a
// too-short distance, a wrong area) fails the first check.
TEST(TexelLaplacian, UvSphereStiffnessComesFromThePoles) {
  struct Case {
    const char* name;
    int rings;
  };
  for (const Case& c : {Case{"64 x 32", 32}, Case{"32 x 16", 16}}) {
    SCOPED_TRACE(c.name);
    Pde p(make_uv_sphere(2 * c.rings, c.rings, 1.0), 512, 512);
    const std::vector<double> rates = cell_rates(p.lap);
    std::vector<double> sorted = rates;
    std::nth_element(sorted.begin(), sorted.begin() + sorted.size() / 2, sorted.end());
    const double median = sorted[sorted.size() / 2];
    double worst = 0;
    size_t stiff = 0, misplaced = 0;
    const double polar_cap = std::cos(25 * kPi / 180);
    for (size_t r = 0; r < rates.size(); ++r) {
      worst = std::max(worst, rates[r]);
      if (rates[r] <= 4 * median) continue;
      ++stiff;
      misplaced += std::fabs(p.centre[p.lap.rows[r]][2]) < polar_cap;
    }
    EXPECT_DOUBLE_EQ(worst, p.lap.max_rate);
    EXPECT_EQ(misplaced, 0u) << "of " << stiff << " cells stiffer than 4x the median";
    EXPECT_LT(p.lap.max_rate / median, 30.0);
    const double dt = 1.0 / 60;
    std::printf("[ sphere %s, 512^2 ] %zu cells: max rate %.3g, median %.3g (x%.1f), %zu cells "
                "> 4x median; sub-steps at dt 1/60 for r_dif 1e-4 / 1e-3 / 1e-2: %u / %u / %u "
                "(median cell alone: %u / %u / %u)\n",
                c.name, p.lap.rows.size(), p.lap.max_rate, median, p.lap.max_rate / median, stiff,
                moldtex::forward_substeps(p.lap, 1e-4, dt), moldtex::forward_substeps(p.lap, 1e-3, dt),
                moldtex::forward_substeps(p.lap, 1e-2, dt), unsigned(std::ceil(median * 1e-4 * dt / 0.9)),
                unsigned(std::ceil(median * 1e-3 * dt / 0.9)), unsigned(std::ceil(median * 1e-2 * dt / 0.9)));
  }
}

}  // namespace
}  // namespace mtx
