// The intrinsic domain (issue 11): concentrations at the vertices of an intrinsic
// Delaunay triangulation, diffused by the cotangent Laplacian, read by agents that walk
// the intrinsic faces, and gathered into the UV texture.
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "backends/cpu/private_sums.h"
#include "domain/intrinsic_domain.h"
#include "domain/texel_laplacian.h"
#include "intrinsic/correspondence.h"
#include "pattern_measures.h"
#include "shared/intrinsic_locate.h"
#include "shared/texel_sampling.h"
#include "surface/surface.h"
#include "test_backends.h"
#include "test_util.h"

namespace mtx {
namespace {

namespace it = moldtex::intrinsic;

struct Domain {
  moldtex::Surface surface;
  moldtex::TextureDomain texture;
  std::shared_ptr<const moldtex::IntrinsicDomain> d;
  Domain(const Mesh& m, uint32_t size, double bound) {
    moldtex::ThreadPool pool(2);
    surface = moldtex::build_surface(m.desc());
    texture = moldtex::build_texture_domain(surface, size, size, pool);
    d = moldtex::intrinsic_domain_for(surface, texture, bound > 0 ? bound : moldtex::default_intrinsic_bound(texture),
                                      0, pool, *moldtex::default_intrinsic_cache());
  }
  Vec3 position(uint32_t v) const {
    const auto p = it::input_position(d->tri, d->vertex_location(v));
    return {p[0], p[1], p[2]};
  }
  // The vertex nearest to x.
  uint32_t nearest(const Vec3& x) const {
    uint32_t best = 0;
    double bd = 1e300;
    for (uint32_t v : d->laplacian.rows) {
      const double dist = norm(sub(position(v), x));
      if (dist < bd) bd = dist, best = v;
    }
    return best;
  }
};

// Amount sum_i M_i u_i and the spread sum_i M_i u_i dist(x_i)^2 / amount.
struct Moments {
  double amount = 0, variance = 0;
};
Moments moments(const Domain& dom, const std::vector<float>& u, const std::function<double(const Vec3&)>& dist) {
  Moments m;
  for (uint32_t v : dom.d->laplacian.rows) {
    const double a = double(dom.d->laplacian.area[v]) * u[v];
    m.amount += a;
    const double r = dist(dom.position(v));
    m.variance += a * r * r;
  }
  m.variance /= m.amount;
  return m;
}

// A unit amount at one vertex spreads like the heat kernel: on a plane E|x - x0|^2 =
// 4 r_dif t. With r_dec = 0 the total is conserved (the operator is symmetric and every
// row sums to 0): within 1e-6 relative (float values, double sums).
TEST(IntrinsicDomain, PointSourceOnAPlaneSpreadsLikeTheHeatKernel) {
  const Mesh m = make_plane(8, 8, -2, -2, 2, 2, [](double x, double y) { return Vec2{(x + 2) / 4, (y + 2) / 4}; });
  Domain dom(m, 128, 0.03);
  const Vec3 x0{0, 0, 0};
  const uint32_t v0 = dom.nearest(x0);
  const Vec3 c = dom.position(v0);
  std::vector<float> u(dom.d->vertex_count(), 0.f), scratch;
  u[v0] = float(1.0 / dom.d->laplacian.area[v0]);
  const double D = 0.01, t = 1.0, dt = 0.05;
  moldtex::ThreadPool pool(2);
  for (int s = 0; s < int(std::lround(t / dt)); ++s)
    moldtex::advance_diffusion_decay(dom.d->laplacian, u.data(), scratch, D, 0.0, dt, MOLDTEX_INTEGRATOR_FORWARD, pool);
  const Moments mo = moments(dom, u, [&](const Vec3& x) { return norm(sub(x, c)); });
  std::printf("vertices %u, amount %.9f, variance %.5f (heat kernel %.5f)\n", dom.d->vertex_count(), mo.amount,
              mo.variance, 4 * D * t);
  EXPECT_NEAR(mo.amount, 1.0, 1e-6);
  EXPECT_NEAR(mo.variance / (4 * D * t), 1.0, 0.05);
}

// On the unit sphere the geodesic spread of a point source for a short time (4 r_dif t =
// 0.01, a spread of 0.1 radii: curvature changes E d^2 by ~ r_dif t / 3 relative, 0.1%) is
// the plane's 4 r_dif t within 5%; backward Euler conserves the total within 1e-6 (the
// conjugate gradients' tolerance, relative).
TEST(IntrinsicDomain, PointSourceOnASphereSpreadsLikeTheHeatKernel) {
  const Mesh m = make_uv_sphere(48, 24, 1.0);
  Domain dom(m, 256, 0.02);
  const Vec3 x0 = normalized(Vec3{0.3, 0.5, 0.2});
  const uint32_t v0 = dom.nearest(x0);
  const Vec3 c = normalized(dom.position(v0));
  for (uint32_t integrator : {MOLDTEX_INTEGRATOR_FORWARD, MOLDTEX_INTEGRATOR_BACKWARD}) {
    std::vector<float> u(dom.d->vertex_count(), 0.f), scratch;
    u[v0] = float(1.0 / dom.d->laplacian.area[v0]);
    const double D = 0.005, t = 0.5, dt = 0.05;
    moldtex::ThreadPool pool(2);
    for (int s = 0; s < int(std::lround(t / dt)); ++s)
      moldtex::advance_diffusion_decay(dom.d->laplacian, u.data(), scratch, D, 0.0, dt, integrator, pool);
    const Moments mo = moments(dom, u, [&](const Vec3& x) {
      return std::acos(std::clamp(dot(normalized(x), c), -1.0, 1.0));
    });
    std::printf("%s: vertices %u, amount %.9f, variance %.5f (heat kernel %.5f)\n",
                integrator == MOLDTEX_INTEGRATOR_FORWARD ? "forward" : "backward", dom.d->vertex_count(), mo.amount,
                mo.variance, 4 * D * t);
    EXPECT_NEAR(mo.amount, 1.0, 1e-5);
    EXPECT_NEAR(mo.variance / (4 * D * t), 1.0, 0.05);
  }
}

// Agents convert to the intrinsic faces and back to where they were (the walker's point
// within 1e-4 of the object's size, its heading within 1e-3 radians): the host spawns,
// brushes and reports agents on the input mesh.
TEST(IntrinsicDomain, AgentsConvertBothWays) {
  const Mesh m = make_torus(32, 16, 1.0, 0.4);
  Domain dom(m, 128, 0);
  uint64_t rng = 12345;
  auto uniform = [&] {
    rng = rng * 6364136223846793005ull + 1442695040888963407ull;
    return double(rng >> 11) * (1.0 / 9007199254740992.0);
  };
  double worst_point = 0, worst_angle = 0;
  for (int i = 0; i < 2000; ++i) {
    moldtex::Walker w{};
    w.triangle = uint32_t(uniform() * m.triangle_count()) % m.triangle_count();
    const double a = std::sqrt(uniform()), b = uniform();
    w.bary[0] = float(1 - a);
    w.bary[1] = float(a * (1 - b));
    w.bary[2] = float(a * b);
    const double angle = 2 * M_PI * uniform();
    w.heading = {float(std::cos(angle)), float(std::sin(angle))};
    const moldtex::Walker there = dom.d->to_intrinsic(w);
    const moldtex::Walker back = dom.d->to_input(there);
    const Vec3 p = add(add(scale(m.corner(w.triangle, 0), w.bary[0]), scale(m.corner(w.triangle, 1), w.bary[1])),
                       scale(m.corner(w.triangle, 2), w.bary[2]));
    const Vec3 q = add(add(scale(m.corner(back.triangle, 0), back.bary[0]), scale(m.corner(back.triangle, 1), back.bary[1])),
                       scale(m.corner(back.triangle, 2), back.bary[2]));
    worst_point = std::max(worst_point, norm(sub(p, q)));
    if (back.triangle == w.triangle)
      worst_angle = std::max(worst_angle, std::fabs(std::remainder(
                                              std::atan2(back.heading.y, back.heading.x) - angle, 2 * M_PI)));
  }
  std::printf("round trip: worst point %.3g, worst heading %.3g rad\n", worst_point, worst_angle);
  EXPECT_LT(worst_point, 1e-4 * 2.8);
  EXPECT_LT(worst_angle, 1e-3);
}

// The locator (shared/intrinsic_locate.h) against the exact trace of the correspondence:
// random points of the input mesh, on a fine input (torus) and a coarse one (the cube:
// 12 triangles, each holding thousands of intrinsic faces). The located point, taken
// back to the input mesh, is where it was within 1e-3 of the bound (float weights: the
// error measured is ~1e-5), and in the face the exact trace finds (all but points within
// round-off of an edge, where either face is right).
TEST(IntrinsicDomain, LocatorFindsThePointsFace) {
  for (const char* name : {"torus", "cube"}) {
    const Mesh m = std::string(name) == "torus" ? make_torus(32, 16, 1.0, 0.4) : make_cube();
    Domain dom(m, 256, 0);
    const moldtex::mtx_surface_tables t = dom.d->tables(moldtex::mtx_surface_tables{});
    uint64_t rng = 99;
    auto uniform = [&] {
      rng = rng * 6364136223846793005ull + 1442695040888963407ull;
      return double(rng >> 11) * (1.0 / 9007199254740992.0);
    };
    double worst = 0;
    int inside = 0;
    const int n = 20000;
    for (int i = 0; i < n; ++i) {
      const uint32_t tri = uint32_t(uniform() * m.triangle_count()) % m.triangle_count();
      const double a = std::sqrt(uniform()), b = uniform();
      const float bary[3] = {float(1 - a), float(a * (1 - b)), float(a * b)};
      float c[3];
      uint32_t v[3];
      const uint32_t f = moldtex::mtx_locate_intrinsic(t.locator_grid, t.locator_cells, t.locator_face, t.locator_map,
                                                        t.locator_next, t.locator_across, t.face_vertices, tri, bary, c,
                                                        v);
      // The vertices come with the face (from the candidate's record or, after a walk,
      // from the face's own list).
      for (int k = 0; k < 3; ++k) ASSERT_EQ(v[k], dom.d->face_vertices[3 * f + k]);
      moldtex::Walker w{};
      w.triangle = f;
      for (int k = 0; k < 3; ++k) w.bary[k] = c[k];
      w.heading = {1, 0};
      const moldtex::Walker back = dom.d->to_input(w);
      auto at = [&](const moldtex::Walker& p) {
        return add(add(scale(m.corner(p.triangle, 0), p.bary[0]), scale(m.corner(p.triangle, 1), p.bary[1])),
                   scale(m.corner(p.triangle, 2), p.bary[2]));
      };
      moldtex::Walker orig{};
      orig.triangle = tri;
      for (int k = 0; k < 3; ++k) orig.bary[k] = bary[k];
      const double err = norm(sub(at(back), at(orig)));
      if (err > 1e-3 * dom.d->bound && std::getenv("MOLDTEX_LOCATE_DEBUG"))
        std::printf("  miss: triangle %u bary %.6f %.6f %.6f -> face %u c %.4f %.4f %.4f, exact face %u, error %.3g bound\n",
                    tri, bary[0], bary[1], bary[2], f, c[0], c[1], c[2], dom.d->to_intrinsic(orig).triangle,
                    err / dom.d->bound);
      worst = std::max(worst, err);
      // Inside: the exact location's face is the located one.
      inside += dom.d->to_intrinsic(orig).triangle == f;
    }
    std::printf("%s: %u vertices, %zu candidates in %zu cells; worst %.3g x bound, same face %.4f\n", name,
                dom.d->vertex_count(), dom.d->locator.face.size() / MTX_LOCATE_FACE_STRIDE, dom.d->locator.cells.size() - 1,
                worst / dom.d->bound, double(inside) / n);
    EXPECT_LT(worst, 1e-3 * dom.d->bound) << name;
    EXPECT_GT(double(inside) / n, 0.99) << name;
  }
}

// The agents' sampling lattice (domain/intrinsic_lattice.h) on a flat mesh, where the
// answer is known: the vertex hats and the lattice's hats each reproduce a linear
// function exactly, so a reading through the lattice of u = x + 2y equals x + 2y at the
// point (float round-off: values of order 4, so within 1e-5), and a deposit passed on
// through the lattice lands whole (integer parts) with its centroid at the point (the
// parts' rounding moves it by at most ~3 units of 2^20 over distances of one lattice
// triangle: 1e-4 of the bound). A wrong node number or weight would be off by a node
// spacing (~0.02 here), 100x the tolerances.
TEST(IntrinsicDomain, LatticeReadsAndDepositsLikeTheHatsOnAPlane) {
  const Mesh m = make_plane(6, 6, -2, -2, 2, 2, [](double x, double y) { return Vec2{(x + 2) / 4, (y + 2) / 4}; });
  Domain dom(m, 128, 0.03);
  const moldtex::IntrinsicLattice& L = dom.d->lattice;
  moldtex::ThreadPool pool(2);
  const uint32_t nv = dom.d->vertex_count(), nodes = L.node_count();
  std::vector<float> u(nv);
  for (uint32_t v = 0; v < nv; ++v) u[v] = float(dom.position(v)[0] + 2 * dom.position(v)[1]);
  std::vector<float> at_nodes(nodes);
  L.gather(u.data(), nv, at_nodes.data(), 1, pool);
  const moldtex::mtx_surface_tables t = dom.d->agent_tables(moldtex::mtx_surface_tables{}, nullptr);
  uint64_t rng = 7;
  auto uniform = [&] {
    rng = rng * 6364136223846793005ull + 1442695040888963407ull;
    return double(rng >> 11) * (1.0 / 9007199254740992.0);
  };
  const int32_t units = 1 << 20;
  std::vector<int32_t> node_sums(nodes, 0), sums(nv, 0);
  moldtex::PrivateSums per_thread;  // the backend's way: each thread its own sums
  per_thread.prepare(nv, pool.size());
  double worst_read = 0, worst_centroid = 0;
  for (int i = 0; i < 5000; ++i) {
    const uint32_t tri = uint32_t(uniform() * m.triangle_count()) % m.triangle_count();
    const double a = std::sqrt(uniform()), b = uniform();
    moldtex::Walker w{};
    w.triangle = tri;
    w.bary[0] = float(1 - a), w.bary[1] = float(a * (1 - b)), w.bary[2] = float(a * b);
    const Vec3 x = add(add(scale(m.corner(tri, 0), w.bary[0]), scale(m.corner(tri, 1), w.bary[1])),
                       scale(m.corner(tri, 2), w.bary[2]));
    moldtex::mtx_texel_stencil st;
    moldtex::mtx_texel_stencil_of(t, &w, 0, 0, 1, &st);
    double read = 0, weights = 0;
    for (int k = 0; k < 4; ++k) {
      ASSERT_LT(st.cell[k], nodes);
      read += st.weight[k] * at_nodes[st.cell[k]];
      weights += st.weight[k];
    }
    ASSERT_NEAR(weights, 1.0, 1e-6);
    worst_read = std::max(worst_read, std::fabs(read - (x[0] + 2 * x[1])));
    // One deposit at a time: through the nodes on to the vertices.
    moldtex::mtx_texel_deposit(node_sums.data(), &st, units, 0);
    std::fill(sums.begin(), sums.end(), 0);
    L.scatter(node_sums.data(), sums.data(), nv, 1, per_thread, pool);
    int64_t total = 0;
    Vec3 centroid{0, 0, 0};
    for (uint32_t v = 0; v < nv; ++v)
      if (sums[v] != 0) {
        total += sums[v];
        centroid = add(centroid, scale(dom.position(v), double(sums[v]) / units));
      }
    ASSERT_EQ(total, units);
    for (int32_t q : node_sums) ASSERT_EQ(q, 0);
    worst_centroid = std::max(worst_centroid, norm(sub(centroid, x)));
  }
  std::printf("lattice: %u nodes for %u vertices; worst reading error %.2g, worst deposit centroid %.2g x bound\n",
              nodes, nv, worst_read, worst_centroid / dom.d->bound);
  EXPECT_LT(worst_read, 1e-5);
  EXPECT_LT(worst_centroid, 1e-4 * dom.d->bound);
}

// A CAD-style open cylinder: one ring of 64 triangles 10 long and 0.005 wide (aspect
// ~2000). A lattice with nodes 0.7 edges apart along the long edges would need ~2000x
// the nodes of well-shaped triangles (millions per triangle, ~2000 per vertex); the
// sliver cap holds the count to ~36x the area-based one (about 2 per vertex), so within
// 100 per vertex (ordinary meshes: 4-5). The cylinder develops onto a plane with z kept, so
// both the exact hats and the lattice reproduce z: a reading within 1e-5 of the height
// (the nodes are traced in double precision; the float locator's cells clamp on such
// slivers, which the exact hats' figure shows).
TEST(IntrinsicDomain, LatticeOfSliversStaysSmall) {
  const Mesh m = make_open_cylinder(64, 1, 0.05, 10.0);
  Domain dom(m, 64, 0.02);
  const moldtex::IntrinsicLattice& L = dom.d->lattice;
  moldtex::ThreadPool pool(2);
  const uint32_t nv = dom.d->vertex_count(), nodes = L.node_count();
  std::printf("slivers: %u nodes for %u vertices (%.1f per vertex)\n", nodes, nv, double(nodes) / nv);
  EXPECT_LT(nodes, 100u * nv);
  std::vector<float> u(nv), at_nodes(nodes);
  for (uint32_t v = 0; v < nv; ++v) u[v] = float(dom.position(v)[2]);
  L.gather(u.data(), nv, at_nodes.data(), 1, pool);
  const moldtex::mtx_surface_tables t = dom.d->agent_tables(moldtex::mtx_surface_tables{}, nullptr);
  double worst = 0, worst_exact = 0;
  int bad = 0, bad_exact = 0;
  const moldtex::mtx_surface_tables exact = dom.d->tables(moldtex::mtx_surface_tables{});
  for (uint32_t tri = 0; tri < m.triangle_count(); ++tri)
    for (int i = 0; i < 50; ++i) {
      moldtex::Walker w{};
      w.triangle = tri;
      const double a = (i + 0.5) / 50, b = std::fmod(0.618034 * i, 1.0);
      w.bary[0] = float(1 - a), w.bary[1] = float(a * (1 - b)), w.bary[2] = float(a * b);
      const double z = w.bary[0] * m.corner(tri, 0)[2] + w.bary[1] * m.corner(tri, 1)[2] + w.bary[2] * m.corner(tri, 2)[2];
      moldtex::mtx_texel_stencil st;
      moldtex::mtx_texel_stencil_of(t, &w, 0, 0, 1, &st);
      double read = 0;
      for (int k = 0; k < 4; ++k) read += st.weight[k] * at_nodes[st.cell[k]];
      worst = std::max(worst, std::fabs(read - z));
      moldtex::mtx_texel_stencil ex;
      moldtex::mtx_texel_stencil_of(exact, &w, 0, 0, 1, &ex);
      double r2 = 0;
      for (int k = 0; k < 4; ++k) r2 += ex.weight[k] * u[ex.cell[k]];
      worst_exact = std::max(worst_exact, std::fabs(r2 - z));
      if (std::fabs(r2 - z) > 1e-3) ++bad_exact;
      if (std::fabs(read - z) > 1e-3) ++bad;
    }
  std::printf("slivers: worst reading error of z %.2g (exact hats %.2g); over 1e-3: %d, %d of %u\n", worst, worst_exact, bad, bad_exact, 50 * m.triangle_count());
  EXPECT_LT(worst, 1e-5 * 10.0);
}

// ---- the simulation on the intrinsic domain, through the C API --------------------

struct RunSpec {
  const Mesh* mesh = nullptr;
  uint32_t size = 128, agents = 20000, threads = 0, domain = MOLDTEX_DOMAIN_INTRINSIC;
  Backend backend = Backend::Cpu;
  uint64_t seed = 1;
  double seconds = 2.0;
  uint32_t snapshots = 0;  // extra ones, 0.5 s apart, ending at `seconds`
  float bound = 0;         // the intrinsic triangles' circumradius bound (0: auto)
  moldtex_continuous_params p = turnover_look();
};

// The pattern measured on the intrinsic vertices themselves (no texture in between):
// the area-weighted mean of u / U and the gradient length mean(u) / mean |grad u| over
// the triangles (area-weighted, the gradient of the linear interpolant in 3D), which is
// proportional to the spacing of the trails (as the texture tests' GradientLength).
struct VertexCharacter {
  double mean = 0, length = 0;
};

VertexCharacter MeasureVertices(moldtex_sim sim) {
  moldtex_domain_info info;
  moldtex_domain_info_init(&info);
  EXPECT_EQ(moldtex_sim_get_domain_info(sim, &info), MOLDTEX_OK) << LastError();
  std::vector<float> xyz(4ull * info.cell_count), u(info.cell_count);
  std::vector<uint32_t> faces(3ull * info.face_count);
  EXPECT_EQ(moldtex_sim_read_intrinsic_vertices(sim, xyz.data(), u.data(), info.cell_count), MOLDTEX_OK) << LastError();
  EXPECT_EQ(moldtex_sim_read_intrinsic_faces(sim, faces.data(), info.face_count), MOLDTEX_OK) << LastError();
  const double U = get_stats(sim).u_metric;
  VertexCharacter c;
  double mass = 0, sum = 0, area = 0, slope = 0;
  for (uint32_t v = 0; v < info.cell_count; ++v) {
    mass += xyz[4 * v + 3];
    sum += double(xyz[4 * v + 3]) * u[v] / U;
  }
  for (uint32_t f = 0; f < info.face_count; ++f) {
    const uint32_t* k = faces.data() + 3 * f;
    auto P = [&](int i) { return Vec3{xyz[4 * k[i]], xyz[4 * k[i] + 1], xyz[4 * k[i] + 2]}; };
    const Vec3 e1 = sub(P(1), P(0)), e2 = sub(P(2), P(0));
    const double a = dot(e1, e1), b = dot(e1, e2), d = dot(e2, e2), det = a * d - b * b;
    if (!(det > 0)) continue;
    const double d1 = (u[k[1]] - u[k[0]]) / U, d2 = (u[k[2]] - u[k[0]]) / U;
    // |grad|^2 = du^T M^-1 du with M = [[a, b], [b, d]].
    const double g2 = (d * d1 * d1 - 2 * b * d1 * d2 + a * d2 * d2) / det;
    const double A = 0.5 * norm(cross(e1, e2));
    area += A;
    slope += A * std::sqrt(std::max(g2, 0.0));
  }
  c.mean = sum / mass;
  c.length = c.mean / (slope / area);
  return c;
}

struct Result {
  std::vector<std::vector<double>> shown;  // u / U per snapshot (channel R)
  moldtex_sim_stats stats{};
  moldtex_domain_info info{};
  std::string backend;
  std::vector<VertexCharacter> vertex;  // per snapshot (intrinsic domain)
};

Result Simulate(const RunSpec& r) {
  Result out;
  auto s = create_surface(*r.mesh);
  EXPECT_TRUE(s) << LastError();
  if (!s) return out;
  moldtex_sim_config c = make_config(r.size, r.size, r.agents, r.seed);
  c.model = MOLDTEX_MODEL_CONTINUOUS;
  c.domain = r.domain;
  c.intrinsic_bound = r.bound;
  std::string why;
  EXPECT_TRUE(PinBackend(r.backend, c, &why)) << why;
  moldtex_sim_params mp = default_params();
  mp.thread_count = r.threads;
  auto sim = create_sim(s.get(), c, mp);
  EXPECT_TRUE(sim) << LastError();
  if (!sim) return out;
  EXPECT_EQ(moldtex_sim_set_continuous_params(sim.get(), &r.p), MOLDTEX_OK) << LastError();
  moldtex_domain_info_init(&out.info);
  EXPECT_EQ(moldtex_sim_get_domain_info(sim.get(), &out.info), MOLDTEX_OK) << LastError();
  char name[256] = {0};
  moldtex_sim_get_backend_name(sim.get(), name, sizeof name);
  out.backend = name;
  for (int k = int(r.snapshots); k >= 0; --k) {
    const double t = r.seconds - 0.5 * k;
    const uint32_t steps = uint32_t(std::lround(t / r.p.time_step)) - uint32_t(get_stats(sim.get()).step_count);
    EXPECT_EQ(moldtex_sim_step(sim.get(), steps), MOLDTEX_OK) << LastError();
    const std::vector<float> rgba = read_rgba(sim.get(), r.size, r.size);
    std::vector<double> f(size_t(r.size) * r.size);
    for (size_t i = 0; i < f.size(); ++i) f[i] = rgba[4 * i];
    out.shown.push_back(std::move(f));
    if (r.domain == MOLDTEX_DOMAIN_INTRINSIC) out.vertex.push_back(MeasureVertices(sim.get()));
  }
  out.stats = get_stats(sim.get());
  return out;
}

const Mesh& Torus() {
  static const Mesh m = make_torus(64, 32, 1.0, 0.4);
  return m;
}

// The continuous model runs on the intrinsic domain: the domain reports its size (about
// as many vertices as island texels: Chew's bound gives 0.4-1.6 vertices per bound^2 of
// area), the backend says where it runs, and the mean concentration settles at U
// (Eq. 5; the same 3% as the texture domain's MeanConcentrationSettlesAtU: binomial
// noise of the live agents, 5 samples).
TEST(IntrinsicSimulation, RunsTheContinuousModelAndSettlesAtU) {
  RunSpec r;
  r.mesh = &Torus();
  r.p.mean_lifetime = 0.f;
  r.p.activation_time = 0.f;
  const Result o = Simulate(r);
  std::printf("%s: %u vertices, %u faces, bound %.4f, built in %.2f s (cache %u); mean %.4f U\n", o.backend.c_str(),
              o.info.cell_count, o.info.face_count, o.info.bound, o.info.build_seconds, o.info.from_cache,
              o.stats.mean_concentration / o.stats.u_metric);
  EXPECT_EQ(o.info.domain, uint32_t(MOLDTEX_DOMAIN_INTRINSIC));
  EXPECT_NE(o.backend.find("intrinsic"), std::string::npos) << o.backend;
  const double island_texels = double(r.size) * r.size;  // the torus' UVs fill the texture
  EXPECT_GT(o.info.cell_count, 0.4 * island_texels);
  EXPECT_LT(o.info.cell_count, 1.6 * island_texels);
  const double area = 4 * M_PI * M_PI * 0.4;
  EXPECT_NEAR(o.stats.u_metric / (r.agents * r.p.deposit_rate / (r.p.decay_rate * area)), 1.0, 0.01);
  EXPECT_NEAR(o.stats.mean_concentration / o.stats.u_metric, 1.0, 0.03);
}

TEST(IntrinsicSimulation, SameSeedSameTextureForAnyThreadCount) {
  RunSpec r;
  r.mesh = &Torus();
  r.seconds = 0.5;
  r.threads = 1;
  const Result one = Simulate(r);
  r.threads = 2;
  const Result two = Simulate(r);
  ASSERT_EQ(one.shown.back().size(), two.shown.back().size());
  EXPECT_TRUE(std::equal(one.shown.back().begin(), one.shown.back().end(), two.shown.back().begin()));
  r.threads = 3;  // two threads with sums of their own (PrivateSums), folded into the first's
  const Result three = Simulate(r);
  ASSERT_EQ(one.shown.back().size(), three.shown.back().size());
  EXPECT_TRUE(std::equal(one.shown.back().begin(), one.shown.back().end(), three.shown.back().begin()));
}

// Each thread adds into its own sums, and the fold gives every add once: the counts of a
// known scatter come out exact, twice in a row (the fold leaves the threads' planes
// clear), and a plane too large to copy per thread falls back to the shared one.
TEST(PrivateSums, FoldsEveryThreadsAddsOnce) {
  moldtex::ThreadPool pool(3);
  moldtex::PrivateSums per_thread;
  constexpr size_t kCells = 1000, kItems = 300000;
  per_thread.prepare(kCells, pool.size());
  ASSERT_TRUE(per_thread.exclusive());
  std::vector<int32_t> shared(kCells, 0);
  std::atomic<unsigned> highest{0};
  for (int round = 1; round <= 2; ++round) {
    pool.parallel_for_threads(kItems, 1000, [&](size_t begin, size_t end, unsigned thread) {
      unsigned was = highest.load();
      while (thread > was && !highest.compare_exchange_weak(was, thread)) {
      }
      int32_t* into = per_thread.for_thread(shared.data(), thread);
      for (size_t i = begin; i < end; ++i) into[(i * 7919) % kCells] += 1;
    });
    per_thread.fold_into(shared.data(), pool);
    for (size_t c = 0; c < kCells; ++c) ASSERT_EQ(shared[c], round * int32_t(kItems / kCells)) << c;
  }
  EXPECT_LT(highest.load(), pool.size());
  per_thread.prepare(moldtex::PrivateSums::kMaxBytes / sizeof(int32_t) / 2 + 1, pool.size());
  EXPECT_FALSE(per_thread.exclusive());
  EXPECT_EQ(per_thread.for_thread(shared.data(), 2), shared.data());
  EXPECT_EQ(per_thread.bytes(), 0u);
}

// The square [0, 4]^2 in 64 x 64 cells, its UVs cut into 16 islands (one per unit
// square, each in its own tile of a 4 x 4 grid, inset so gutter fits between them, every
// other one turned half a turn): UV seams run across a flat surface where nothing else
// changes, so any difference near them is the seams' doing.
Mesh make_cut_plane() {
  Mesh m = make_plane(64, 64, 0, 0, 4, 4, [](double x, double y) { return Vec2{x / 4, y / 4}; });
  std::vector<float> uvs;
  for (uint32_t t = 0; t < m.triangle_count(); ++t) {
    const Vec3 c = scale(add(add(m.corner(t, 0), m.corner(t, 1)), m.corner(t, 2)), 1.0 / 3);
    const int bx = std::min(3, int(c[0])), by = std::min(3, int(c[1]));
    const bool turned = (bx + by) % 2 == 1;
    for (int k = 0; k < 3; ++k) {
      const Vec3 p = m.corner(t, k);
      double lx = p[0] - bx, ly = p[1] - by;
      if (turned) lx = 1 - lx, ly = 1 - ly;
      uvs.push_back(float((bx + 0.04 + 0.92 * lx) / 4));
      uvs.push_back(float((by + 0.04 + 0.92 * ly) / 4));
    }
  }
  m.uvs = uvs;
  m.triangle_uvs.clear();
  return m;
}

// Fig. 12: pheromone in the texels within 2 texels of a UV seam against the texels
// farther from every seam, both away from the plane's open boundary (0.5 units, where
// the walls change the pattern): on the intrinsic domain the ratio is within [0.9, 1.1]
// (the bound), over 6 seeds x 6 snapshots 0.5 s apart. The texture domain's
// ratio is printed beside it (one seed): 1.4-2.3 on this layout, issue 9's to fix.
// With 2 seeds, as until 2026-12-05, the ratio read 0.96, 1.13, 1.03 and 1.06 for
// seeds 1-2 and the same seeds shifted by 1000, 2000 and 3000
// (MOLDTEX_TEST_SEED_OFFSET): a 2-seed ratio spreads by ~0.07, so it held by luck.
// Six seeds narrow that to ~0.04: they read 1.007, and 1.041 shifted by 1000.
TEST(IntrinsicSimulation, NoTraceOfTheUvSeams) {
  const Mesh plane = make_cut_plane();
  RunSpec r;
  r.mesh = &plane;
  r.size = 256;
  r.seconds = 4.0;
  r.snapshots = 6;
  r.agents = 40000;
  const TexelGeometry g = Texels(plane, r.size, r.size);
  const uint32_t n = r.size;
  auto away_from_walls = [&](size_t i) {
    const Vec3& p = g.position[i];
    return std::min({p[0], p[1], 4 - p[0], 4 - p[1]}) > 0.5;
  };
  auto near_seam = [&](uint32_t x, uint32_t y) {
    for (int dy = -2; dy <= 2; ++dy)
      for (int dx = -2; dx <= 2; ++dx) {
        const int xx = int(x) + dx, yy = int(y) + dy;
        if (xx < 0 || yy < 0 || xx >= int(n) || yy >= int(n) || !g.inside(size_t(yy) * n + xx)) return true;
      }
    return false;
  };
  for (uint32_t domain : {MOLDTEX_DOMAIN_TEXTURE, MOLDTEX_DOMAIN_INTRINSIC}) {
    r.domain = domain;
    double seam = 0, inner = 0, samples = 0;
    for (uint64_t seed : {1, 2, 3, 4, 5, 6}) {
      if (domain == MOLDTEX_DOMAIN_TEXTURE && seed > 1) break;  // for comparison only
      r.seed = seed;
      const Result o = Simulate(r);
      for (const auto& f : o.shown) {
        seam += Mean(g, f, [&](uint32_t x, uint32_t y) { return away_from_walls(size_t(y) * n + x) && near_seam(x, y); });
        inner += Mean(g, f, [&](uint32_t x, uint32_t y) { return away_from_walls(size_t(y) * n + x) && !near_seam(x, y); });
        samples += 1;
      }
    }
    std::printf("%s domain: within 2 texels of a seam %.4f U, elsewhere %.4f U, ratio %.3f\n",
                domain == MOLDTEX_DOMAIN_TEXTURE ? "texture" : "intrinsic", seam / samples, inner / samples, seam / inner);
    if (domain == MOLDTEX_DOMAIN_INTRINSIC) {
      EXPECT_GT(seam / inner, 0.9);
      EXPECT_LT(seam / inner, 1.1);
    }
  }
}

// The mean vertex character over seeds 1 and 2 and 5 snapshots 0.5 s apart.
VertexCharacter VertexCharacter2(RunSpec r, uint64_t first = 1) {
  VertexCharacter sum;
  r.snapshots = 4;
  for (uint64_t seed : {first, first + 1}) {
    r.seed = seed;
    const Result o = Simulate(r);
    for (const VertexCharacter& c : o.vertex) {
      sum.mean += c.mean / (2.0 * o.vertex.size());
      sum.length += c.length / (2.0 * o.vertex.size());
    }
  }
  return sum;
}

::testing::AssertionResult Similar(const VertexCharacter& a, const VertexCharacter& b, double tol) {
  const double dm = std::fabs(a.mean / b.mean - 1), dl = std::fabs(a.length / b.length - 1);
  std::printf("  mean %.4f U, length %.4f vs mean %.4f U, length %.4f: differences %.3f, %.3f\n", a.mean, a.length,
              b.mean, b.length, dm, dl);
  if (dm <= tol && dl <= tol) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "differences " << dm << ", " << dl << " (tolerance " << tol << ")";
}

// Fig. 4: a sphere triangulated with long twisted slivers (each band joins ring vertex j
// to j + 3 of the next ring) against the ordinary triangulation of the same vertices:
// the intrinsic triangulation makes them the same simulation domain, so the pattern
// measures agree within 10% (the bound). Both spheres have 128 segments and 32
// rings, so their polyhedra approximate the same sphere (a coarse twisted sphere would be
// another shape). The seed-to-seed spread of these measures: see the next test.
TEST(IntrinsicSimulation, SkinnyTrianglesGiveTheSamePattern) {
  Mesh good = make_twisted_sphere(128, 32, 0), skinny = make_twisted_sphere(128, 32, 8);
  give_atlas_uvs(good);
  give_atlas_uvs(skinny);
  RunSpec r;
  r.size = 128;
  r.seconds = 3.0;
  r.agents = 30000;
  r.bound = 0.03f;
  r.p.diffusion_rate = 0.01f;  // trails sqrt(r_dif / r_dec) = 0.04 wide: resolved at 0.03
  r.mesh = &good;
  const VertexCharacter a = VertexCharacter2(r);
  r.mesh = &skinny;
  const VertexCharacter b = VertexCharacter2(r);
  EXPECT_TRUE(Similar(a, b, 0.1));
}

// Fig. 10b: halving the circumradius bound (about 4x the vertices) changes the pattern
// measures by less than 10% once the bound resolves the pattern (0.03 is a third of the
// sensor distance; the trails are a few sensor distances apart). Seeds 3 and 4 against
// 1 and 2 at the same bound give the noise floor, printed.
TEST(IntrinsicSimulation, HalvingTheBoundKeepsThePattern) {
  RunSpec r;
  r.mesh = &Torus();
  r.size = 128;
  r.seconds = 3.0;
  r.agents = 30000;
  r.bound = 0.03f;
  r.p.diffusion_rate = 0.01f;  // trails sqrt(r_dif / r_dec) = 0.04 wide
  const VertexCharacter coarse = VertexCharacter2(r);
  std::printf("noise floor (seeds 3, 4 against 1, 2):\n");
  Similar(VertexCharacter2(r, 3), coarse, 0.1);
  r.bound = 0.015f;
  const VertexCharacter fine = VertexCharacter2(r);
  EXPECT_TRUE(Similar(coarse, fine, 0.1));
}

// What the add-on does with a running simulation works on the intrinsic domain too: the
// slime brush adds agents (on the mesh) and undo removes them; the erase brush; and a
// checkpoint (which holds the vertex values themselves) resumes bit for bit: 20 steps
// after loading give the texture 20 steps after saving gave.
TEST(IntrinsicSimulation, BrushesAndCheckpointsWork) {
  auto s = create_surface(Torus());
  ASSERT_TRUE(s);
  moldtex_sim_config c = make_config(128, 128, 5000, 3);
  c.model = MOLDTEX_MODEL_CONTINUOUS;
  c.domain = MOLDTEX_DOMAIN_INTRINSIC;
  auto sim = create_sim(s.get(), c, default_params());
  ASSERT_TRUE(sim) << LastError();
  ASSERT_EQ(moldtex_sim_step(sim.get(), 30), MOLDTEX_OK) << LastError();
  moldtex_brush b;
  moldtex_brush_init(&b);
  b.center.triangle = 100;
  b.radius = 0.2f;
  ASSERT_EQ(moldtex_sim_add_agents(sim.get(), &b, 700, 1), MOLDTEX_OK) << LastError();
  EXPECT_EQ(get_stats(sim.get()).agent_count, 5700u);
  ASSERT_EQ(moldtex_sim_step(sim.get(), 5), MOLDTEX_OK) << LastError();
  uint32_t removed = 0;
  ASSERT_EQ(moldtex_sim_erase_agents(sim.get(), &b, 2, &removed), MOLDTEX_OK) << LastError();
  EXPECT_GT(removed, 0u);
  ASSERT_EQ(moldtex_sim_undo_agents(sim.get(), 2), MOLDTEX_OK) << LastError();
  ASSERT_EQ(moldtex_sim_undo_agents(sim.get(), 1), MOLDTEX_OK) << LastError();
  EXPECT_EQ(get_stats(sim.get()).agent_count, 5000u);
  const std::string path = ::testing::TempDir() + "/moldtex_intrinsic_checkpoint.bin";
  ASSERT_EQ(moldtex_sim_save_checkpoint(sim.get(), path.c_str()), MOLDTEX_OK) << LastError();
  const moldtex_sim_stats saved = get_stats(sim.get());
  ASSERT_EQ(moldtex_sim_step(sim.get(), 20), MOLDTEX_OK) << LastError();
  const std::vector<float> straight = read_rgba(sim.get(), 128, 128);
  ASSERT_EQ(moldtex_sim_load_checkpoint(sim.get(), path.c_str()), MOLDTEX_OK) << LastError();
  EXPECT_EQ(get_stats(sim.get()).step_count, saved.step_count);
  EXPECT_EQ(get_stats(sim.get()).mean_concentration, saved.mean_concentration);
  ASSERT_EQ(moldtex_sim_step(sim.get(), 20), MOLDTEX_OK) << LastError();
  const std::vector<float> resumed = read_rgba(sim.get(), 128, 128);
  EXPECT_TRUE(straight == resumed) << "a resumed run differs from the straight one";
  std::remove(path.c_str());
}

// Both backends run the intrinsic domain from the same shared source: the OpenCL device
// gives the CPU's pattern in character (the vertex measures within 5%: the device's own
// sin/cos/exp rounding makes the runs diverge in detail, and the seed-to-seed spread of
// these measures is ~1%, see HalvingTheBoundKeepsThePattern), and the total within
// 0.5% (U's noise over 5 snapshots of 20 000 agents is ~0.3%). Skipped without an OpenCL
// device (failed under MOLDTEX_REQUIRE_OPENCL=1, as in CI).
TEST(IntrinsicBackends, OpenClAgreesWithTheCpu) {
  RunSpec r;
  r.mesh = &Torus();
  r.seconds = 2.5;
  r.p.diffusion_rate = 0.01f;
  moldtex_sim_config probe = make_config(8, 8, 1, 1);
  std::string why;
  if (!PinBackend(Backend::OpenCl, probe, &why)) {
    if (OpenClRequiredByEnv()) FAIL() << "MOLDTEX_REQUIRE_OPENCL is set: " << why;
    GTEST_SKIP() << why;
  }
  const VertexCharacter cpu = VertexCharacter2(r);
  r.backend = Backend::OpenCl;
  const Result one = Simulate(r);
  EXPECT_NE(one.backend.find("OpenCL"), std::string::npos) << one.backend;
  const VertexCharacter device = VertexCharacter2(r);
  EXPECT_TRUE(Similar(device, cpu, 0.05));
  EXPECT_NEAR(device.mean / cpu.mean, 1.0, 0.005);
}

// MoMaS works in texels; OpenCL does not run the intrinsic domain yet: both refused with
// a message that says what to choose instead.
// Fig. 12, UV stretch: a 4 x 4 plane whose UVs are warped u -> u^2, so a texel on the
// left covers far less surface than one on the right. The texture the user sees (the
// intrinsic vertices gathered into it) must show the same characteristic length in 3D
// in both halves within 10% (the bound), as the texture domain's own test does
// (ContinuousModel.StretchedUvsDoNotChangeTheLengthIn3D); 2 seeds.
TEST(IntrinsicSimulation, StretchedUvsDoNotChangeTheLengthIn3D) {
  static const Mesh warped = make_uv_squared_plane(64);
  RunSpec r;
  r.mesh = &warped;
  r.size = 512;
  r.agents = 40000;
  double left = 0, right = 0;
  for (uint64_t seed : {1, 2}) {
    r.seed = seed;
    const Result out = Simulate(r);
    ASSERT_FALSE(out.shown.empty());
    const TexelGeometry g = Texels(warped, r.size, r.size);
    for (int half = 0; half < 2; ++half) {
      TexelGeometry h = g;
      for (size_t i = 0; i < h.triangle.size(); ++i) {
        if (!h.inside(i)) continue;
        const double x = h.position[i][0], y = h.position[i][1];
        // 3D halves, away from the plane's border (0.3 units) and from the middle.
        const bool in = half == 0 ? (x > 0.3 && x < 1.8) : (x > 2.2 && x < 3.7);
        if (!in || y < 0.3 || y > 3.7) h.triangle[i] = -1;
      }
      (half == 0 ? left : right) += GradientLength(h, out.shown.back()) / 2;
    }
  }
  std::printf("intrinsic domain, gradient length in 3D: compressed half %.4f, stretched half %.4f (ratio %.3f)\n",
              left, right, left / right);
  EXPECT_NEAR(left / right, 1.0, 0.10);
}

// A mesh without UVs runs on the intrinsic domain: the UVs enter only the texture write
// (and the order agents are regrouped in memory, so runs differ seed-like, not bit for
// bit). With the bound given (by default it follows the island texels), the torus
// without UVs shows the pattern measures of the torus with them within 5% (seed-to-seed
// spread of these measures: 0.7%, HalvingTheBoundKeepsThePattern). Its result per mesh
// vertex (moldtex_sim_read_vertex_rgba) is u / U at the intrinsic vertex that is that
// mesh vertex (the same 3D point), R = G = B, A = 1, on the CPU and on OpenCL; a
// texture-domain sim answers that call with an error.
TEST(IntrinsicSimulation, RunsOnAMeshWithoutUvs) {
  const Mesh& with = Torus();
  Mesh without = with;
  without.uvs.clear();
  without.triangle_uvs.clear();
  {
    RunSpec r;
    r.size = 128;
    r.seconds = 3.0;
    r.agents = 30000;
    r.bound = 0.03f;
    r.p.diffusion_rate = 0.01f;  // as HalvingTheBoundKeepsThePattern
    r.mesh = &with;
    const VertexCharacter a = VertexCharacter2(r);
    r.mesh = &without;
    const VertexCharacter b = VertexCharacter2(r);
    EXPECT_TRUE(Similar(a, b, 0.05));
  }

  auto surface = create_surface(without);
  ASSERT_TRUE(surface) << LastError();
  moldtex_sim_config c = make_config(64, 64, 5000, 3);
  c.model = MOLDTEX_MODEL_CONTINUOUS;
  c.domain = MOLDTEX_DOMAIN_INTRINSIC;
  std::vector<float> rgba(4ull * without.vertex_count());
  for (Backend backend : {Backend::Cpu, Backend::OpenCl}) {
    std::string why;
    if (!PinBackend(backend, c, &why)) {
      std::printf("no UVs on OpenCL: skipped (%s)\n", why.c_str());
      continue;
    }
    SCOPED_TRACE(backend == Backend::Cpu ? "CPU" : "OpenCL");
    auto sim = create_sim(surface.get(), c, default_params());
    ASSERT_TRUE(sim) << LastError();
    const moldtex_continuous_params p = turnover_look();
    ASSERT_EQ(moldtex_sim_set_continuous_params(sim.get(), &p), MOLDTEX_OK) << LastError();
    ASSERT_EQ(moldtex_sim_step(sim.get(), uint32_t(std::lround(0.5 / p.time_step))), MOLDTEX_OK) << LastError();
    moldtex_domain_info info;
    moldtex_domain_info_init(&info);
    ASSERT_EQ(moldtex_sim_get_domain_info(sim.get(), &info), MOLDTEX_OK);
    std::vector<float> xyz(4ull * info.cell_count), u(info.cell_count);
    ASSERT_EQ(moldtex_sim_read_intrinsic_vertices(sim.get(), xyz.data(), u.data(), info.cell_count), MOLDTEX_OK)
        << LastError();
    ASSERT_EQ(moldtex_sim_read_vertex_rgba(sim.get(), rgba.data(), rgba.size()), MOLDTEX_OK) << LastError();
    EXPECT_EQ(moldtex_sim_read_vertex_rgba(sim.get(), rgba.data(), rgba.size() - 1),
              MOLDTEX_ERROR_INVALID_ARGUMENT);
    const double U = get_stats(sim.get()).u_metric;
    double worst_value = 0, worst_position = 0, mean = 0;
    for (uint32_t i = 0; i < without.vertex_count(); ++i) {
      const Vec3 x = without.vertex(i);
      uint32_t best = 0;
      double bd = 1e300;
      for (uint32_t v = 0; v < info.cell_count; ++v) {
        const double dist = norm(sub(Vec3{xyz[4 * v], xyz[4 * v + 1], xyz[4 * v + 2]}, x));
        if (dist < bd) bd = dist, best = v;
      }
      worst_position = std::max(worst_position, bd);
      worst_value = std::max(worst_value, std::fabs(rgba[4 * i] - u[best] / U) / std::max(1.0, u[best] / U));
      EXPECT_EQ(rgba[4 * i], rgba[4 * i + 1]);
      EXPECT_EQ(rgba[4 * i], rgba[4 * i + 2]);
      EXPECT_EQ(rgba[4 * i + 3], 1.f);
      mean += rgba[4 * i];
    }
    mean /= without.vertex_count();
    std::printf("no UVs (%s): %u intrinsic vertices; per mesh vertex: worst position %.2g, worst value %.2g, "
                "mean %.3f U\n",
                backend == Backend::Cpu ? "CPU" : "OpenCL", info.cell_count, worst_position, worst_value, mean);
    EXPECT_LT(worst_position, 1e-5);  // the torus is 2.8 units across: float rounding
    EXPECT_LT(worst_value, 1e-5);     // the same float, divided by U in double
    EXPECT_GT(mean, 0.2);             // a pattern grew (the mean of u / U nears 1 as the agents settle)
  }

  auto textured = create_surface(with);
  ASSERT_TRUE(textured);
  c.domain = MOLDTEX_DOMAIN_TEXTURE;
  c.backend = MOLDTEX_BACKEND_CPU;
  auto texture_sim = create_sim(textured.get(), c, default_params());
  ASSERT_TRUE(texture_sim) << LastError();
  EXPECT_EQ(moldtex_sim_read_vertex_rgba(texture_sim.get(), rgba.data(), rgba.size()),
            MOLDTEX_ERROR_INVALID_ARGUMENT);
  EXPECT_NE(LastError().find("texture domain"), std::string::npos) << LastError();
}

// The intrinsic domain's simulation never reads a UV coordinate: the agents walk the
// mesh in 3D frames, the PDE lives on the intrinsic vertices, and the agents are
// regrouped in memory by mesh triangle (not by texture tile, which would put the UV
// layout into their order and so into their random streams). So one torus with its own
// UVs, with the UVs turned a quarter turn and halved (another layout), with every
// triangle its own UV island (the worst unwrap), and without UVs gives the same
// concentration at every intrinsic vertex, bit for bit, at a set bound. (The default
// bound comes from the texture's texel size, so it would differ between layouts.) Only
// the texture gathered from those vertices depends on the UVs.
TEST(IntrinsicSimulation, TheUvLayoutDoesNotEnterTheResult) {
  const Mesh& own = Torus();
  Mesh turned = own, shattered = own, without = own;
  for (size_t i = 0; i + 1 < turned.uvs.size(); i += 2) {
    const float u = turned.uvs[i], v = turned.uvs[i + 1];
    turned.uvs[i] = 0.25f + 0.5f * (1.f - v);
    turned.uvs[i + 1] = 0.25f + 0.5f * u;
  }
  shattered.uvs.clear();
  shattered.triangle_uvs.clear();
  const uint32_t per_side = uint32_t(std::ceil(std::sqrt(double(own.triangle_count()))));
  for (uint32_t t = 0; t < own.triangle_count(); ++t) {
    const float x = float(t % per_side) / per_side, y = float(t / per_side) / per_side, d = 0.8f / per_side;
    const float corner[6] = {x, y, x + d, y, x, y + d};
    shattered.uvs.insert(shattered.uvs.end(), corner, corner + 6);
  }
  without.uvs.clear();
  without.triangle_uvs.clear();
  auto run = [](const Mesh& m, Backend backend) {
    auto s = create_surface(m);
    EXPECT_TRUE(s) << LastError();
    moldtex_sim_config c = make_config(128, 128, 20000, 5);
    c.model = MOLDTEX_MODEL_CONTINUOUS;
    c.domain = MOLDTEX_DOMAIN_INTRINSIC;
    c.intrinsic_bound = 0.03f;
    std::vector<float> u;
    std::string why;
    if (!PinBackend(backend, c, &why)) {
      std::printf("OpenCL: skipped (%s)\n", why.c_str());
      return u;
    }
    auto sim = create_sim(s.get(), c, default_params());
    EXPECT_TRUE(sim) << LastError();
    if (!sim) return u;
    const moldtex_continuous_params p = turnover_look();
    EXPECT_EQ(moldtex_sim_set_continuous_params(sim.get(), &p), MOLDTEX_OK) << LastError();
    // 1 s: 60 steps, past three regroupings of the agents (every 16 steps).
    EXPECT_EQ(moldtex_sim_step(sim.get(), uint32_t(std::lround(1.0 / p.time_step))), MOLDTEX_OK) << LastError();
    moldtex_domain_info info;
    moldtex_domain_info_init(&info);
    EXPECT_EQ(moldtex_sim_get_domain_info(sim.get(), &info), MOLDTEX_OK);
    std::vector<float> xyz(4ull * info.cell_count);
    u.resize(info.cell_count);
    EXPECT_EQ(moldtex_sim_read_intrinsic_vertices(sim.get(), xyz.data(), u.data(), info.cell_count), MOLDTEX_OK)
        << LastError();
    return u;
  };
  for (Backend backend : {Backend::Cpu, Backend::OpenCl}) {
    SCOPED_TRACE(backend == Backend::Cpu ? "CPU" : "OpenCL");
    const std::vector<float> reference = run(own, backend);
    if (reference.empty() && backend == Backend::OpenCl) continue;  // no device (said above)
    ASSERT_FALSE(reference.empty());
    double sum = 0;
    for (float v : reference) sum += v;
    EXPECT_GT(sum, 0.0);  // deposits were made: the comparison is not of empty fields
    const struct {
      const char* name;
      const Mesh* mesh;
    } layouts[] = {{"turned and halved", &turned}, {"one island per triangle", &shattered}, {"no UVs", &without}};
    for (const auto& l : layouts) {
      const std::vector<float> u = run(*l.mesh, backend);
      ASSERT_EQ(u.size(), reference.size()) << l.name;
      size_t differ = 0;
      for (size_t i = 0; i < u.size(); ++i) differ += u[i] != reference[i];
      EXPECT_EQ(differ, 0u) << l.name << ": " << differ << " of " << u.size() << " vertices differ";
    }
  }
}

// A 4 x 1 plane whose UVs collapse over the strip 1.875 <= x <= 2.125 (two columns of
// faces with zero UV area, as a careless unwrap or a pinned UV edge leaves them). The
// texture domain cannot measure texels there, so those faces are walls to its agents;
// the intrinsic domain needs no UVs to walk, so its agents cross them. All agents start
// at (1, 0.5) with uniform headings and no pheromone to steer by (deposit 0), moving
// 0.6 units/s for 3 s: about a third head right far enough to pass x = 2.125 (a straight
// path from x = 1 crosses it within 1.8 units when its heading is within ~51 degrees of
// +x, and reflections off the long sides keep it going). With walls none can.
Mesh make_collapsed_strip_plane() {
  auto u_of = [](double x) { return x <= 1.875 ? x : (x >= 2.125 ? x - 0.25 : 1.875); };
  return make_plane(32, 8, 0.0, 0.0, 4.0, 1.0, [&](double x, double y) { return Vec2{u_of(x) / 3.75, y}; });
}

TEST(IntrinsicSimulation, AgentsWalkAcrossFacesWithZeroUvArea) {
  const Mesh m = make_collapsed_strip_plane();
  auto surface = create_surface(m);
  ASSERT_TRUE(surface) << LastError();
  // The intrinsic domain built ahead, as Start does in the interface: the simulations
  // below find it in the cache (DomainBuild walks the same surface as they do). The
  // bound (0.031) is not the default (0.03125 here), so no earlier test built this one.
  const float bound = 0.031f;
  {
    moldtex_sim_config c = make_config(64, 64, 4000, 5);
    c.model = MOLDTEX_MODEL_CONTINUOUS;
    c.domain = MOLDTEX_DOMAIN_INTRINSIC;
    c.intrinsic_bound = bound;
    moldtex_domain_build build = nullptr;
    ASSERT_EQ(moldtex_domain_build_start(surface.get(), &c, 0, &build), MOLDTEX_OK) << LastError();
    ASSERT_EQ(moldtex_domain_build_wait(build), MOLDTEX_OK) << LastError();
    moldtex_domain_build_release(build);
  }
  for (uint32_t domain : {uint32_t(MOLDTEX_DOMAIN_INTRINSIC), uint32_t(MOLDTEX_DOMAIN_TEXTURE)}) {
    for (Backend backend : {Backend::Cpu, Backend::OpenCl}) {
      moldtex_sim_config c = make_config(64, 64, 4000, 5);
      c.model = MOLDTEX_MODEL_CONTINUOUS;
      c.domain = domain;
      c.intrinsic_bound = domain == MOLDTEX_DOMAIN_INTRINSIC ? bound : 0.f;
      c.seed_shape = MOLDTEX_SEED_BIG_BANG;
      c.seed_center = locate(m, {1.0, 0.5, 0.0});
      std::string why;
      if (!PinBackend(backend, c, &why)) {
        std::printf("OpenCL: skipped (%s)\n", why.c_str());
        continue;
      }
      auto sim = create_sim(surface.get(), c, default_params());
      ASSERT_TRUE(sim) << LastError();
      moldtex_continuous_params p;
      moldtex_continuous_params_init(&p);
      p.deposit_rate = 0.f;
      ASSERT_EQ(moldtex_sim_set_continuous_params(sim.get(), &p), MOLDTEX_OK) << LastError();
      if (domain == MOLDTEX_DOMAIN_INTRINSIC) {
        moldtex_domain_info info;
        moldtex_domain_info_init(&info);
        ASSERT_EQ(moldtex_sim_get_domain_info(sim.get(), &info), MOLDTEX_OK) << LastError();
        EXPECT_EQ(info.from_cache, 1u);
      }
      ASSERT_EQ(moldtex_sim_step(sim.get(), uint32_t(std::lround(3.0 / p.time_step))), MOLDTEX_OK) << LastError();
      std::vector<moldtex_surface_point> at(c.agent_count);
      ASSERT_EQ(moldtex_sim_read_agents(sim.get(), at.data(), at.size()), MOLDTEX_OK) << LastError();
      size_t right = 0, strip = 0;
      for (const moldtex_surface_point& a : at) {
        const double x = m.point(a)[0];
        right += x > 2.125 + 1e-4;
        strip += x > 1.875 + 1e-4 && x < 2.125 - 1e-4;
      }
      const double share = double(right) / at.size();
      std::printf("%s domain, %s: %.3f of the agents beyond the strip, %zu on it\n",
                  domain == MOLDTEX_DOMAIN_INTRINSIC ? "intrinsic" : "texture",
                  backend == Backend::Cpu ? "CPU" : "OpenCL", share, strip);
      if (domain == MOLDTEX_DOMAIN_INTRINSIC) {
        EXPECT_GT(share, 0.15);  // measured about a third; the wall gives 0
        EXPECT_LT(share, 0.6);   // most start heading elsewhere
      } else {
        EXPECT_EQ(right, 0u);  // the texture domain's walls (README: known limit)
        EXPECT_EQ(strip, 0u);
      }
    }
  }
}

// A needle found by the fuzzer: one triangle 5.5e11 units long and about 1 wide. The
// texel-derived bound (3.5e4) allows about 400 vertices by the surface's area, but
// mollification widened the needle in the triangulation's own lengths, and refinement,
// capped by that inflated area (1e9 insertions), ran for minutes filling memory. The cap
// now comes from the mesh's true area: the build stops after a few thousand insertions
// and says what to do (a larger bound, or the Texture domain).
TEST(IntrinsicSimulation, ANeedleIsRefusedInBoundedWork) {
  Mesh needle;
  needle.positions = {0, 0, 0, 1, 0, -5.49755814e+11f, 0.5f, 1, 0, 0, 1, 0};
  needle.triangles = {0, 1, 2, 0, 2, 3};
  auto s = create_surface(needle);  // no UVs: the placeholder layout
  ASSERT_TRUE(s) << LastError();
  moldtex_sim_config c = make_config(16, 16, 36, 1);
  c.model = MOLDTEX_MODEL_CONTINUOUS;
  c.domain = MOLDTEX_DOMAIN_INTRINSIC;
  c.backend = MOLDTEX_BACKEND_CPU;
  moldtex_status status = MOLDTEX_OK;
  EXPECT_FALSE(create_sim(s.get(), c, default_params(), &status));
  EXPECT_EQ(status, MOLDTEX_ERROR_TOO_LARGE);
  EXPECT_NE(LastError().find("Raise the bound"), std::string::npos) << LastError();
}

TEST(IntrinsicSimulation, RefusesWhatItDoesNotRun) {
  auto s = create_surface(Torus());
  ASSERT_TRUE(s);
  moldtex_sim_config c = make_config(64, 64, 100, 1);
  c.domain = MOLDTEX_DOMAIN_INTRINSIC;
  moldtex_status status;
  EXPECT_FALSE(create_sim(s.get(), c, default_params(), &status));
  EXPECT_NE(LastError().find("Texture domain"), std::string::npos) << LastError();
  c.model = MOLDTEX_MODEL_CONTINUOUS;
  c.intrinsic_bound = std::nanf("");
  EXPECT_FALSE(create_sim(s.get(), c, default_params(), &status));
  EXPECT_NE(LastError().find("bound"), std::string::npos) << LastError();
  c.intrinsic_bound = 0;
  c.domain = 7;
  EXPECT_FALSE(create_sim(s.get(), c, default_params(), &status));
  EXPECT_NE(LastError().find("Unknown domain"), std::string::npos) << LastError();
}

}  // namespace
}  // namespace mtx
