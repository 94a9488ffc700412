// The intrinsic Delaunay triangulation (src/intrinsic, issue 11): connectivity,
// mollification, Delaunay flips, refinement, the correspondence with the input mesh and
// the cotangent operators. White-box: these tests call the core's C++ directly (see
// CMakeLists.txt); the C API has no intrinsic domain yet.
//
// Every check is one a geometry-processing paper would make, on inputs chosen to be bad
// (long slivers, fans, needles at poles, a tiny input angle), and each tolerance says
// where it comes from. Measured values are printed (RecordProperty and stdout) so a
// regression shows by how much.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>

#include <Eigen/Dense>

#include "common/error.h"
#include "intrinsic/correspondence.h"
#include "intrinsic/delaunay_flip.h"
#include "intrinsic/intrinsic_operators.h"
#include "intrinsic/mollification.h"
#include "intrinsic/refinement.h"
#include "surface/surface.h"
#include "test_util.h"

namespace mtx {
namespace {

namespace it = moldtex::intrinsic;

std::vector<double> positions_of(const Mesh& m) { return std::vector<double>(m.positions.begin(), m.positions.end()); }

it::IntrinsicTriangulation build(const Mesh& m) { return it::build_intrinsic_triangulation(positions_of(m), m.triangles); }

// Rectangle [0, W] x [0, H] with N + 1 vertices on the bottom and top sides, triangulated
// as two fans: the bottom vertices all joined to the top-left corner, the top ones to the
// bottom-right corner. Every triangle is a long sliver (angles down to ~atan(W/N / H)
// at the fans' apexes) and most interior edges are far from Delaunay.
Mesh make_sliver_strip(int N, double W, double H) {
  std::vector<Vec3> p;
  for (int i = 0; i <= N; ++i) p.push_back({W * i / N, 0, 0});  // B_i = i
  for (int i = 0; i <= N; ++i) p.push_back({W * i / N, H, 0});  // T_i = N + 1 + i
  std::vector<uint32_t> t;
  const uint32_t T0 = N + 1;
  for (int i = 0; i < N; ++i) t.insert(t.end(), {uint32_t(i), uint32_t(i + 1), T0});
  for (int i = 0; i < N; ++i) t.insert(t.end(), {T0 + i + 1, T0 + i, uint32_t(N)});
  return mesh_from(p, t);
}

// Open cylinder band (radius 1, height H, n segments) whose triangles join bottom vertex
// j to top vertex j + shift: long twisted slivers, a bad triangulation of an annulus.
Mesh make_twisted_band(int n, int shift, double H) {
  std::vector<Vec3> p;
  for (int j = 0; j < n; ++j) p.push_back({std::cos(2 * M_PI * j / n), std::sin(2 * M_PI * j / n), 0});
  for (int j = 0; j < n; ++j) p.push_back({std::cos(2 * M_PI * j / n), std::sin(2 * M_PI * j / n), H});
  std::vector<uint32_t> t;
  auto B = [&](int j) { return uint32_t(((j % n) + n) % n); };
  auto T = [&](int j) { return uint32_t(n + ((j % n) + n) % n); };
  for (int j = 0; j < n; ++j) {
    t.insert(t.end(), {B(j), B(j + 1), T(j + shift)});
    t.insert(t.end(), {B(j + 1), T(j + shift + 1), T(j + shift)});
  }
  return mesh_from(p, t);
}

// n x n grid on [0, 1]^2 whose middle row of vertices is moved onto the next row (and
// half a cell sideways): the band between them is 2n triangles of zero area (three
// collinear vertices), which only mollification makes usable.
Mesh make_collapsed_band(int n) {
  std::vector<Vec3> p;
  const double h = 1.0 / n;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) {
      if (j == n / 2)
        p.push_back({i * h + 0.5 * h, (j + 1) * h, 0});
      else
        p.push_back({i * h, j * h, 0});
    }
  std::vector<uint32_t> t;
  auto V = [&](int i, int j) { return uint32_t(j * (n + 1) + i); };
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      t.insert(t.end(), {V(i, j), V(i + 1, j), V(i + 1, j + 1)});
      t.insert(t.end(), {V(i, j), V(i + 1, j + 1), V(i, j + 1)});
    }
  return mesh_from(p, t);
}

// Both meshes as one (separate components).
Mesh concatenate(const Mesh& a, const Mesh& b) {
  Mesh m = a;
  m.positions.insert(m.positions.end(), b.positions.begin(), b.positions.end());
  for (uint32_t v : b.triangles) m.triangles.push_back(v + a.vertex_count());
  return m;
}

double bbox_diagonal(const Mesh& m) {
  Vec3 lo{1e300, 1e300, 1e300}, hi{-1e300, -1e300, -1e300};
  for (uint32_t v = 0; v < m.vertex_count(); ++v)
    for (int i = 0; i < 3; ++i) lo[i] = std::min(lo[i], m.vertex(v)[i]), hi[i] = std::max(hi[i], m.vertex(v)[i]);
  return norm(sub(hi, lo));
}

// Largest (opposite angle sum - pi) over interior edges, and how many exceed tol.
std::pair<double, uint32_t> delaunay_violation(const it::IntrinsicMesh& m, double tol) {
  double worst = -M_PI;
  uint32_t bad = 0;
  for (uint32_t e = 0; e < m.edge_count(); ++e) {
    if (m.is_boundary_edge(e)) continue;
    const double v = it::opposite_angle_sum(m, e) - M_PI;
    worst = std::max(worst, v);
    bad += v > tol;
  }
  return {worst, bad};
}

Vec3 to3(const std::array<double, 3>& a) { return {a[0], a[1], a[2]}; }

// A uniformly random point of a random input face.
it::SurfacePoint random_input_point(const it::IntrinsicTriangulation& T, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(0, 1);
  it::SurfacePoint p;
  p.face = uint32_t(u(rng) * T.input.face_count()) % T.input.face_count();
  const double r1 = std::sqrt(u(rng)), r2 = u(rng);
  p.bary = {1 - r1, r1 * (1 - r2), r1 * r2};
  return p;
}

// ---- connectivity --------------------------------------------------------------------

TEST(IntrinsicMesh, ConnectivityOfAPlaneWithBoundary) {
  // 4 x 3 cells: V = 20, E = 3 * 4 * 3 + 4 + 3 = 43, F = 24, boundary edges 2 * (4 + 3),
  // Euler characteristic 1 (a disk); total angles: pi/2 at the four corners, pi at the
  // other boundary vertices, 2 pi inside.
  const Mesh m = make_plane(4, 3, 0, 0, 4, 3, [](double x, double y) { return Vec2{x / 4, y / 3}; });
  const auto T = build(m);
  const auto& im = T.input;
  EXPECT_EQ(im.vertex_count(), 20u);
  EXPECT_EQ(im.edge_count(), 43u);
  EXPECT_EQ(im.face_count(), 24u);
  EXPECT_EQ(im.euler_characteristic(), 1);
  EXPECT_EQ(T.mollify_epsilon, 0.0);  // well-shaped triangles keep their lengths exactly
  uint32_t boundary_edges = 0, boundary_vertices = 0;
  for (uint32_t e = 0; e < im.edge_count(); ++e) boundary_edges += im.is_boundary_edge(e);
  EXPECT_EQ(boundary_edges, 14u);
  for (uint32_t v = 0; v < im.vertex_count(); ++v) {
    const Vec3 x = m.vertex(v);
    const bool bx = x[0] == 0 || x[0] == 4, by = x[1] == 0 || x[1] == 3;
    boundary_vertices += im.boundary[v];
    EXPECT_EQ(bool(im.boundary[v]), bx || by) << v;
    const double expected = (bx && by) ? M_PI / 2 : (bx || by) ? M_PI : 2 * M_PI;
    EXPECT_NEAR(im.angle_sum[v], expected, 1e-12) << v;
  }
  EXPECT_EQ(boundary_vertices, 14u);
  EXPECT_NEAR(im.total_area(), 12.0, 1e-12);
}

TEST(IntrinsicMesh, UvSeamsDoNotCutTheSurface) {
  // The UV sphere's triangles meet along a UV seam (longitude 0) and at the poles (each
  // fan corner has its own UV), but share positions there: built from the validated
  // Surface, the intrinsic mesh is a closed sphere (no boundary, Euler characteristic 2)
  // and a path across the seam crosses it like any other edge.
  const Mesh m = make_uv_sphere(24, 12, 1.0);
  const moldtex_mesh_desc desc = m.desc();
  const moldtex::Surface surface = moldtex::build_surface(desc);
  ASSERT_GT(surface.seam_edges, 0u);
  const auto T = it::build_intrinsic_triangulation(surface);
  EXPECT_EQ(T.input.euler_characteristic(), 2);
  for (uint32_t e = 0; e < T.input.edge_count(); ++e) ASSERT_FALSE(T.input.is_boundary_edge(e)) << e;
  for (uint32_t v = 0; v < T.input.vertex_count(); ++v) {
    EXPECT_FALSE(T.input.boundary[v]);
    // Every vertex of a convex polyhedron is a cone of total angle < 2 pi.
    EXPECT_LT(T.input.angle_sum[v], 2 * M_PI);
    EXPECT_GT(T.input.angle_sum[v], 1.5 * M_PI);
  }
}

TEST(IntrinsicMesh, RefusesNonManifoldInputAndDropsRepeatedIndices) {
  // Non-manifold: refused with a message that counts the edges and says how to find them.
  try {
    build(make_nonmanifold_fan());
    FAIL() << "non-manifold input accepted";
  } catch (const moldtex::Error& e) {
    EXPECT_EQ(e.status(), MOLDTEX_ERROR_INVALID_MESH);
    EXPECT_NE(std::string(e.what()).find("edge"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("Non Manifold"), std::string::npos) << e.what();
  }
  // Two fans sharing only a vertex (a bow tie): refused too.
  const Mesh bowtie = mesh_from({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {-1, 0, 0}, {0, -1, 0}}, {0, 1, 2, 0, 3, 4});
  EXPECT_THROW(build(bowtie), moldtex::Error);
  // A triangle repeating a vertex has no interior: dropped and counted, the rest kept.
  Mesh quad = make_quad();
  quad.triangles.insert(quad.triangles.end(), {0, 0, 1});
  const auto T = build(quad);
  EXPECT_EQ(T.dropped_triangles, 1u);
  EXPECT_EQ(T.input.face_count(), 2u);
}

TEST(IntrinsicMesh, MollificationGivesZeroAreaTrianglesAreaAndKeepsOthers) {
  // A quad split so that one triangle is degenerate: vertex 3 on the edge (0, 1).
  const Mesh m = mesh_from({{0, 0, 0}, {2, 0, 0}, {1, 1, 0}, {1, 0, 0}}, {0, 3, 2, 3, 1, 2, 0, 1, 3});
  // (0, 1, 3) has zero area: its three lengths 2, 1, 1 meet l0 = l1 + l2 exactly.
  const auto T = build(m);
  const double delta = it::kDefaultMollifyMargin * T.mean_edge;
  // eps = delta - (1 + 1 - 2) = delta: the smallest shift that gives the margin.
  EXPECT_NEAR(T.mollify_epsilon, delta, 1e-15);
  for (uint32_t f = 0; f < T.input.face_count(); ++f) {
    const auto h = T.input.face_halfedges(f);
    for (int i = 0; i < 3; ++i)
      EXPECT_GE(T.input.len(h[(i + 1) % 3]) + T.input.len(h[(i + 2) % 3]) - T.input.len(h[i]), delta * (1 - 1e-9));
    EXPECT_GT(T.input.face_area(f), 0.0);
    EXPECT_TRUE(std::isfinite(T.input.circumradius(f)));
  }
}

// ---- Delaunay flips -------------------------------------------------------------------

TEST(IntrinsicFlip, SliverInputsBecomeDelaunay) {
  struct Case {
    const char* name;
    Mesh mesh;
    int64_t euler;
  };
  const Case cases[] = {{"sliver strip", make_sliver_strip(40, 4, 1), 1},
                        {"twisted band", make_twisted_band(48, 6, 1), 0},
                        {"twisted sphere", make_twisted_sphere(48, 12, 5), 2},
                        {"zero-area band", make_collapsed_band(16), 1}};
  for (const Case& c : cases) {
    auto T = build(c.mesh);
    const auto before = delaunay_violation(T.mesh, 1e-9);
    // The inputs are bad: edges violate the condition by far (else this test proves
    // nothing): the measured worst excesses are 2.6, 1.0 and 2.0 rad.
    EXPECT_GE(before.second, 1u) << c.name;
    EXPECT_GT(before.first, 0.5) << c.name;
    const uint32_t V = T.mesh.vertex_count(), E = T.mesh.edge_count(), F = T.mesh.face_count();
    const double area = T.mesh.total_area();
    const auto rep = it::flip_to_delaunay(T.mesh);
    EXPECT_FALSE(rep.capped) << c.name;
    EXPECT_GT(rep.flips, 0u) << c.name;
    const auto after = delaunay_violation(T.mesh, 1e-9);
    // Flipping stops at pi + 1e-12; 1e-9 leaves room for the angles' round-off.
    EXPECT_EQ(after.second, 0u) << c.name << ": worst excess " << after.first;
    EXPECT_EQ(T.mesh.vertex_count(), V);
    EXPECT_EQ(T.mesh.edge_count(), E);
    EXPECT_EQ(T.mesh.face_count(), F);
    EXPECT_EQ(T.mesh.euler_characteristic(), c.euler) << c.name;
    // Flips re-cut the same flat quads: the area is unchanged up to round-off (1e-9
    // relative is ~1e6 ulps per face for ~1000 faces).
    EXPECT_NEAR(T.mesh.total_area(), area, 1e-9 * area) << c.name;
    // Every vertex's angle sum (its curvature) is intrinsic: unchanged.
    for (uint32_t v = 0; v < V; ++v) {
      double sum = 0;
      for (uint32_t h = T.mesh.vertex_he[v]; h != it::kInvalid;) {
        sum += T.mesh.corner_angle(h);
        h = T.mesh.ccw_next(h);
        if (h == T.mesh.vertex_he[v]) break;
      }
      EXPECT_NEAR(sum, T.input.angle_sum[v], 1e-9) << c.name << " vertex " << v;
    }
    std::printf("[ measure  ] %s: %u of %u edges non-Delaunay before (worst excess %.3f rad), %llu flips, after: worst %.2e\n",
                c.name, before.second, E, before.first, (unsigned long long)rep.flips, after.first);
  }
}

TEST(IntrinsicFlip, FlatPlaneStaysFlatAndLaplacianIsLinearPrecise) {
  // The sliver strip [0,4] x [0,1], flipped and refined (interior vertices inserted),
  // must stay the same flat rectangle: every intrinsic vertex maps (correspondence) to a
  // point of z = 0 inside the rectangle, every intrinsic edge is as long as the straight
  // segment between its mapped ends (the rectangle is convex, so geodesics are segments),
  // and the cotangent Laplacian of the coordinate functions vanishes at interior vertices.
  const Mesh m = make_sliver_strip(40, 4, 1);
  auto T = build(m);
  it::RefineOptions opt;
  opt.max_circumradius = 0.1;
  const auto rep = it::refine(T, opt);
  ASSERT_EQ(rep.reason, it::StopReason::Converged) << rep.message;
  const auto& im = T.mesh;
  ASSERT_GT(im.vertex_count(), 100u);
  std::vector<Vec3> x(im.vertex_count());
  double worst_z = 0, worst_len = 0;
  for (uint32_t v = 0; v < im.vertex_count(); ++v) {
    x[v] = to3(it::input_position(T, T.corr.location[v]));
    worst_z = std::max(worst_z, std::abs(x[v][2]));
    EXPECT_GE(x[v][0], -1e-12);
    EXPECT_LE(x[v][0], 4 + 1e-12);
    EXPECT_GE(x[v][1], -1e-12);
    EXPECT_LE(x[v][1], 1 + 1e-12);
  }
  for (uint32_t e = 0; e < im.edge_count(); ++e) {
    const double l3 = norm(sub(x[im.tail(2 * e)], x[im.head(2 * e)]));
    worst_len = std::max(worst_len, std::abs(l3 - im.length[e]) / im.length[e]);
  }
  EXPECT_LE(worst_z, 1e-12);
  // 1e-9 relative: round-off of traces a few faces long (1e-16 per operation).
  EXPECT_LE(worst_len, 1e-9);
  const auto ops = it::build_intrinsic_operators(im);
  double worst_lx = 0;
  for (int c = 0; c < 2; ++c) {
    Eigen::VectorXd u(im.vertex_count());
    for (uint32_t v = 0; v < im.vertex_count(); ++v) u[v] = x[v][c];
    const Eigen::VectorXd Ku = ops.stiffness * u;
    for (uint32_t v = 0; v < im.vertex_count(); ++v)
      if (!im.boundary[v]) worst_lx = std::max(worst_lx, std::abs(Ku[v]));
  }
  // K u is a sum of O(1) cotangent weights times coordinates O(1): 1e-9 absolute.
  EXPECT_LE(worst_lx, 1e-9);
  std::printf("[ measure  ] flat strip refined: %u vertices, |z| <= %.1e, edge length vs 3D rel <= %.1e, |K x| <= %.1e\n",
              im.vertex_count(), worst_z, worst_len, worst_lx);
}

// ---- refinement -----------------------------------------------------------------------

TEST(IntrinsicRefinement, CircumradiusBoundAndVertexCount) {
  struct Case {
    const char* name;
    Mesh mesh;
    double bound;
  };
  const Case cases[] = {{"sliver strip 4x1", make_sliver_strip(40, 4, 1), 0.05},
                        {"twisted band", make_twisted_band(48, 6, 1), 0.08},
                        {"uv sphere", make_uv_sphere(32, 16, 1.0), 0.08},
                        {"zero-area band", make_collapsed_band(16), 0.03},
                        {"cube + open cylinder (two components)",
                         concatenate(make_cube(), make_open_cylinder(24, 4, 0.5, 1.0)), 0.05}};
  for (const Case& c : cases) {
    auto T = build(c.mesh);
    const double area = T.mesh.total_area();
    const int64_t euler = T.mesh.euler_characteristic();
    it::RefineOptions opt;
    opt.max_circumradius = c.bound;
    const auto rep = it::refine(T, opt);
    EXPECT_EQ(rep.reason, it::StopReason::Converged) << c.name << ": " << rep.message;
    uint32_t over = 0;
    for (uint32_t f = 0; f < T.mesh.face_count(); ++f) over += T.mesh.circumradius(f) > c.bound;
    // Faces left over the bound are exactly the ones the guards counted; these inputs
    // have no input angle below 60 degrees (the uv sphere's poles: 32 * 11.25 deg
    // around), so none.
    EXPECT_EQ(over, rep.skipped_small_angle + rep.skipped_other) << c.name;
    EXPECT_EQ(over, 0u) << c.name;
    EXPECT_EQ(delaunay_violation(T.mesh, 1e-9).second, 0u) << c.name;
    EXPECT_NEAR(T.mesh.total_area(), area, 1e-9 * area) << c.name;
    EXPECT_EQ(T.mesh.euler_characteristic(), euler) << c.name;  // the same surface
    // Size: circumradii between ~bound/2 and bound give ~[0.4, 1.6] area / bound^2
    // vertices; allow [0.3, 2.0] (boundary vertices and the input's own vertices add).
    const double expected = area / (c.bound * c.bound);
    const double ratio = T.mesh.vertex_count() / expected;
    EXPECT_GE(ratio, 0.3) << c.name;
    EXPECT_LE(ratio, 2.0) << c.name;
    std::printf("[ measure  ] %s: bound %.3f, %u vertices = %.2f x area/bound^2, %llu insertions, %llu boundary splits, "
                "%llu flips, given up %llu\n",
                c.name, c.bound, T.mesh.vertex_count(), ratio, (unsigned long long)rep.insertions,
                (unsigned long long)rep.boundary_splits, (unsigned long long)rep.flips, (unsigned long long)rep.given_up);
  }
}

TEST(IntrinsicRefinement, TerminatesWithATinyInputAngle) {
  // Two inputs with an angle far below 60 degrees, refined far below their size:
  //  * a 2-degree boundary corner at the origin (the tip of a thin wedge O A B, widened by
  //    the triangle A C B, which has a 1.7-degree corner at C), where each split of one
  //    wedge side would encroach the other;
  //  * the apex of a tall open pyramid, a cone point whose total angle is ~23 degrees.
  // Refinement must converge (not hit the cap), leave over the bound only faces at such
  // sharp vertices (counted as skipped), and stay of the expected size.
  const double a = 2 * M_PI / 180;
  struct Case {
    const char* name;
    Mesh mesh;
    uint32_t sharp;  // the vertex with the tiny angle
    double bound;
  };
  const Case cases[] = {
      {"2-degree wedge", mesh_from({{0, 0, 0}, {2, 0, 0}, {2 * std::cos(a), 2 * std::sin(a), 0}, {2.5, 1, 0}},
                                   {0, 1, 2, 1, 3, 2}),
       0, 0.02},
      {"sharp pyramid",
       mesh_from({{0, 0, 2}, {-0.1, -0.1, 0}, {0.1, -0.1, 0}, {0.1, 0.1, 0}, {-0.1, 0.1, 0}},
                 {0, 1, 2, 0, 2, 3, 0, 3, 4, 0, 4, 1}),
       0, 0.03}};
  for (const Case& c : cases) {
    auto T = build(c.mesh);
    EXPECT_LT(T.input.angle_sum[c.sharp], M_PI / 6) << c.name;
    const double area = T.mesh.total_area();
    it::RefineOptions opt;
    opt.max_circumradius = c.bound;
    const auto rep = it::refine(T, opt);
    EXPECT_EQ(rep.reason, it::StopReason::Converged) << c.name << ": " << rep.message;
    uint32_t over = 0, over_not_at_sharp = 0;
    for (uint32_t f = 0; f < T.mesh.face_count(); ++f) {
      if (!(T.mesh.circumradius(f) > opt.max_circumradius)) continue;
      ++over;
      bool at_sharp = false;
      for (uint32_t h : T.mesh.face_halfedges(f)) {
        const uint32_t v = T.mesh.tail(h);
        at_sharp |= v < T.input_vertex_count && T.input.angle_sum[v] < M_PI / 3;
      }
      over_not_at_sharp += !at_sharp;
    }
    EXPECT_EQ(over, rep.skipped_small_angle) << c.name;
    EXPECT_EQ(over_not_at_sharp, 0u) << c.name;
    // Bounded: the faces at the sharp vertex are few (its valence), and the vertex count
    // stays within the usual [0.3, 2] x area / bound^2 plus the input's vertices.
    EXPECT_LE(over, 12u) << c.name;
    const double ratio = T.mesh.vertex_count() / (area / (c.bound * c.bound));
    EXPECT_GE(ratio, 0.3) << c.name;
    EXPECT_LE(ratio, 2.0) << c.name;
    EXPECT_EQ(delaunay_violation(T.mesh, 1e-9).second, 0u) << c.name;
    std::printf("[ measure  ] %s (total angle %.1f deg): %u vertices = %.2f x area/bound^2, %llu insertions, %llu "
                "splits, %u faces at the sharp vertex left over the bound, given up %llu\n",
                c.name, T.input.angle_sum[c.sharp] * 180 / M_PI, T.mesh.vertex_count(), ratio,
                (unsigned long long)rep.insertions, (unsigned long long)rep.boundary_splits, over,
                (unsigned long long)rep.given_up);
  }
  it::RefineOptions opt;
  opt.max_circumradius = 0.02;
  // And the cap works: a cap of 5 insertions stops with a message.
  auto T2 = build(make_sliver_strip(40, 4, 1));
  opt.max_insertions = 5;
  const auto rep2 = it::refine(T2, opt);
  EXPECT_EQ(rep2.reason, it::StopReason::InsertionCap);
  EXPECT_EQ(rep2.insertions + rep2.boundary_splits, 5u);
  EXPECT_NE(rep2.message.find("larger bound"), std::string::npos) << rep2.message;
}

// ---- correspondence -------------------------------------------------------------------

TEST(IntrinsicCorrespondence, RoundTripOnSeveralMeshes) {
  struct Case {
    const char* name;
    Mesh mesh;
    double bound;
  };
  const Case cases[] = {{"uv sphere", make_uv_sphere(32, 16, 1.0), 0.1},
                        {"torus", make_torus(32, 16, 1.0, 0.3), 0.06},
                        {"sliver strip", make_sliver_strip(40, 4, 1), 0.06},
                        {"twisted band", make_twisted_band(48, 6, 1), 0.1},
                        {"twisted sphere", make_twisted_sphere(48, 12, 5), 0.1},
                        {"zero-area band", make_collapsed_band(16), 0.025}};
  std::mt19937_64 rng(11);
  for (const Case& c : cases) {
    auto T = build(c.mesh);
    it::RefineOptions opt;
    opt.max_circumradius = c.bound;
    const auto rep = it::refine(T, opt);
    ASSERT_EQ(rep.reason, it::StopReason::Converged) << c.name;
    const double diag = bbox_diagonal(c.mesh);
    // Intrinsic vertices' input points are points of the input surface: a valid face and
    // barycentric weights in [0, 1] summing to 1.
    for (uint32_t v = 0; v < T.mesh.vertex_count(); ++v) {
      const auto& p = T.corr.location[v];
      ASSERT_LT(p.face, T.input.face_count()) << c.name << " vertex " << v;
      EXPECT_NEAR(p.bary[0] + p.bary[1] + p.bary[2], 1.0, 1e-12);
      for (double b : p.bary) EXPECT_GE(b, 0.0);
    }
    // Every intrinsic edge is a geodesic of the surface between its ends' input points, so
    // no shorter than the straight 3D chord between them (a misplaced vertex shows up as
    // a chord longer than the edge); on these meshes short edges are nearly straight.
    double worst_chord = 0;
    for (uint32_t e = 0; e < T.mesh.edge_count(); ++e) {
      const Vec3 a = to3(it::input_position(T, T.corr.location[T.mesh.tail(2 * e)]));
      const Vec3 b = to3(it::input_position(T, T.corr.location[T.mesh.head(2 * e)]));
      worst_chord = std::max(worst_chord, norm(sub(a, b)) / T.mesh.length[e] - 1);
    }
    EXPECT_LE(worst_chord, 1e-9) << c.name;
    // Input point -> intrinsic -> input: the same 3D point within 1e-6 of the diagonal
    // (the issue asks 1e-5; the traces are a few faces long, round-off ~1e-13). A 1e-4 rad
    // error in the inserted vertices' frame angles gives ~1e-4 x diagonal here.
    // The way back starts at the intrinsic corner nearest to the point; when that is an
    // inserted vertex (counted: most samples on refined meshes), the round trip goes
    // through its stored location and frame angle, not just back along the same line.
    double worst = 0;
    int via_inserted = 0;
    for (int i = 0; i < 2000; ++i) {
      // Every third point on an input edge (boundary edges included), every tenth at an
      // input vertex: lines along edges and through vertices are the fragile cases.
      auto p = random_input_point(T, rng);
      if (i % 3 == 0) p.bary = {p.bary[0] + p.bary[2], p.bary[1], 0.0};
      if (i % 10 == 0) p.bary = {0.0, 1.0, 0.0};
      const auto q = it::to_intrinsic(T, p);
      ASSERT_LT(q.face, T.mesh.face_count());
      const auto L = T.mesh.layout(q.face);
      const it::Vec2d x = q.bary[0] * L[0] + q.bary[1] * L[1] + q.bary[2] * L[2];
      int k = 0;
      for (int j = 1; j < 3; ++j)
        if (it::norm(L[j] - x) < it::norm(L[k] - x)) k = j;
      via_inserted += T.mesh.tail(T.mesh.face_halfedges(q.face)[k]) >= T.input_vertex_count;
      const auto back = it::to_input(T, q);
      worst = std::max(worst, norm(sub(to3(it::input_position(T, back)), to3(it::input_position(T, p)))));
    }
    EXPECT_LE(worst, 1e-6 * diag) << c.name;
    EXPECT_GT(via_inserted, 500) << c.name;
    std::printf("[ measure  ] %s: %u intrinsic vertices, round trip worst %.2e x diagonal (%d of 2000 "
                "via inserted vertices), chord/length - 1 <= %.1e\n",
                c.name, T.mesh.vertex_count(), worst / diag, via_inserted, worst_chord);
  }
}

// ---- operators ------------------------------------------------------------------------

// Mass-weighted relative error of Delta z = -M^-1 K z against -2 z (on the unit sphere z
// is an eigenfunction of the Laplace-Beltrami operator, eigenvalue -2; equivalently
// Delta x = -2 H n with mean curvature H = 1).
double sphere_z_error(const it::IntrinsicMesh& im, const Mesh& mesh) {
  const auto ops = it::build_intrinsic_operators(im);
  Eigen::VectorXd z(im.vertex_count());
  for (uint32_t v = 0; v < im.vertex_count(); ++v) z[v] = mesh.vertex(v)[2];
  const Eigen::VectorXd Kz = ops.stiffness * z;
  double num = 0, den = 0;
  for (uint32_t v = 0; v < im.vertex_count(); ++v) {
    if (!(ops.mass[v] > 0)) continue;
    const double lap = -Kz[v] / ops.mass[v];
    num += ops.mass[v] * (lap + 2 * z[v]) * (lap + 2 * z[v]);
    den += ops.mass[v] * 4 * z[v] * z[v];
  }
  return std::sqrt(num / den);
}

// Dirichlet energy u^T K u of the coordinate function c (the vertices' 3D coordinate,
// interpolated linearly over the intrinsic triangles) and its Rayleigh quotient.
std::pair<double, double> dirichlet(const it::IntrinsicMesh& im, const Mesh& mesh, int c) {
  const auto ops = it::build_intrinsic_operators(im);
  Eigen::VectorXd u(im.vertex_count());
  double den = 0;
  for (uint32_t v = 0; v < im.vertex_count(); ++v) u[v] = mesh.vertex(v)[c], den += ops.mass[v] * u[v] * u[v];
  const double energy = u.dot(ops.stiffness * u);
  return {energy, energy / den};
}

// The three smallest non-zero eigenvalues of K u = lambda M u (dense: small meshes only).
std::array<double, 3> low_eigenvalues(const it::IntrinsicMesh& im) {
  const auto ops = it::build_intrinsic_operators(im);
  const Eigen::MatrixXd K = Eigen::MatrixXd(ops.stiffness);
  const Eigen::MatrixXd M = Eigen::VectorXd::Map(ops.mass.data(), Eigen::Index(ops.mass.size())).asDiagonal();
  Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> es(K, M);
  const auto& ev = es.eigenvalues();
  return {ev[1], ev[2], ev[3]};
}

double worst_eigen_error(const std::array<double, 3>& ev) {
  double w = 0;
  for (double e : ev) w = std::max(w, std::abs(e - 2.0) / 2.0);
  return w;
}

TEST(IntrinsicOperators, SphereLaplacianIsSaneAndDelaunayRepairsBadTriangulations) {
  // (1) Pointwise, on a well-shaped UV sphere (64 x 32), the cotangent Laplacian of z is
  // -2 z up to the discretisation error: measured 0.017 (mass-weighted relative), most of
  // it at the two poles (valence 64: Delta z there is -1.50 instead of -2). Tolerance
  // 0.03. Only on the input's own triangles: on an intrinsic triangulation whose edges
  // cross the mesh's bends, the linear interpolant of z is no longer the 3D z.
  const Mesh fine = make_twisted_sphere(64, 32, 0);
  const auto Tf = build(fine);
  const double err_fine = sphere_z_error(Tf.input, fine);
  EXPECT_LE(err_fine, 0.03);

  // (2) Eigenvalues (intrinsic, so valid on any triangulation of the surface): the unit
  // sphere's first non-zero eigenvalue is 2 (multiplicity 3: x, y, z). A 32 x 16 UV
  // sphere gives 1.9917, 2.0041, 2.0041 (O(h^2) error, h = pi/16); tolerance 2%.
  const Mesh good = make_twisted_sphere(32, 16, 0);
  auto T = build(good);
  const auto ev_good = low_eigenvalues(T.input);
  EXPECT_LE(worst_eigen_error(ev_good), 0.02);

  // (3) A bad triangulation of the same surface: the good mesh re-cut by random intrinsic
  // flips (the metric is untouched, only the triangles change: long slivers with obtuse
  // angles). Its Laplacian is bad (eigenvalues measured up to 2.94, the Rayleigh quotient
  // of z ~90 instead of 2); after Delaunay flips it must be as good as the good mesh's.
  std::mt19937 rng(5);
  uint64_t random_flips = 0;
  for (uint32_t i = 0; i < 10 * T.mesh.edge_count(); ++i) random_flips += it::flip_edge(T.mesh, rng() % T.mesh.edge_count());
  EXPECT_NEAR(T.mesh.total_area(), T.input.total_area(), 1e-9 * T.input.total_area());
  const auto ev_bad = low_eigenvalues(T.mesh);
  const double ray_bad = dirichlet(T.mesh, good, 2).second;
  EXPECT_GT(worst_eigen_error(ev_bad), 0.2);
  it::flip_to_delaunay(T.mesh);
  const auto ev_fixed = low_eigenvalues(T.mesh);
  EXPECT_LE(worst_eigen_error(ev_fixed), 0.02);
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(ev_fixed[i], ev_good[i], 0.005) << i;
  double ray_fixed[3];
  for (int c = 0; c < 3; ++c) {
    ray_fixed[c] = dirichlet(T.mesh, good, c).second;
    EXPECT_NEAR(ray_fixed[c], 2.0, 0.04) << c;  // the Rayleigh quotient of x, y, z: 2
  }

  // (4) Rippa / Bobenko-Springborn: of all triangulations of a surface's vertex set, the
  // (intrinsic) Delaunay one has the least Dirichlet energy for every vertex function. On
  // the twisted-sliver sphere (a different surface: its chords cut inside the sphere),
  // the energy of each coordinate function must not rise by flipping (1e-9 relative:
  // round-off).
  const Mesh twisted = make_twisted_sphere(32, 16, 3);
  auto Tt = build(twisted);
  it::flip_to_delaunay(Tt.mesh);
  double drop[3];
  for (int c = 0; c < 3; ++c) {
    const double before = dirichlet(Tt.input, twisted, c).first, after = dirichlet(Tt.mesh, twisted, c).first;
    EXPECT_LE(after, before * (1 + 1e-9)) << c;
    drop[c] = after / before;
  }
  std::printf("[ measure  ] sphere: Delta z vs -2z (64x32 input) %.4f; eigenvalues good %.4f %.4f %.4f, randomly "
              "flipped (%llu flips) %.4f %.4f %.4f (Rayleigh z %.1f), after Delaunay %.4f %.4f %.4f (Rayleigh x y z "
              "%.4f %.4f %.4f); twisted sphere energy after/before x %.3f y %.3f z %.3f\n",
              err_fine, ev_good[0], ev_good[1], ev_good[2], (unsigned long long)random_flips, ev_bad[0], ev_bad[1],
              ev_bad[2], ray_bad, ev_fixed[0], ev_fixed[1], ev_fixed[2], ray_fixed[0], ray_fixed[1], ray_fixed[2],
              drop[0], drop[1], drop[2]);
}

}  // namespace
}  // namespace mtx

namespace mtx {
namespace {

// ---- robustness -----------------------------------------------------------------------

TEST(IntrinsicRobustness, JitteredTorusWithCoincidentVertices) {
  // Tori whose vertices are jittered by up to half a cell (slivers, obtuse and nearly
  // degenerate triangles), with random diagonals, every tenth vertex moved onto a
  // neighbour (zero-length edges, zero-area triangles: only mollification makes them
  // usable) and, for every third seed, a band of triangles removed (open boundary). The
  // whole pipeline must hold its invariants on every one: refinement converges with no
  // face left over the bound, every interior edge Delaunay, area kept (1e-9 relative,
  // after mollification), round trips within 1e-6 of the diagonal (measured <= 2e-10).
  for (int seed = 0; seed < 12; ++seed) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> U(-1, 1);
    const int nu = 12 + seed % 7, nv = 8 + seed % 5;
    std::vector<Vec3> p;
    for (int i = 0; i < nu; ++i)
      for (int j = 0; j < nv; ++j) {
        const double a = 2 * M_PI * (i + 0.499 * U(rng)) / nu, b = 2 * M_PI * (j + 0.499 * U(rng)) / nv;
        p.push_back({(1 + 0.4 * std::cos(b)) * std::cos(a), (1 + 0.4 * std::cos(b)) * std::sin(a), 0.4 * std::sin(b)});
      }
    auto V = [&](int i, int j) { return uint32_t(((i + nu) % nu) * nv + (j + nv) % nv); };
    for (int i = 0; i < nu; ++i)
      for (int j = 0; j < nv; ++j)
        if (rng() % 10 == 0) p[V(i, j)] = p[V(i + 1, j + seed % 2)];
    std::vector<uint32_t> t;
    for (int i = 0; i < nu; ++i)
      for (int j = 0; j < nv; ++j) {
        if (rng() % 2)
          t.insert(t.end(), {V(i, j), V(i + 1, j), V(i + 1, j + 1), V(i, j), V(i + 1, j + 1), V(i, j + 1)});
        else
          t.insert(t.end(), {V(i, j), V(i + 1, j), V(i, j + 1), V(i + 1, j), V(i + 1, j + 1), V(i, j + 1)});
      }
    if (seed % 3 == 0) t.erase(t.begin(), t.begin() + 6 * nv);
    const Mesh mesh = mesh_from(p, t);
    auto T = build(mesh);
    // Even seeds merge edge neighbours: zero-length edges, so mollification must act.
    if (seed % 2 == 0) {
      EXPECT_GT(T.mollify_epsilon, 0.0) << "seed " << seed;
    }
    const double area = T.mesh.total_area();
    it::RefineOptions opt;
    opt.max_circumradius = 0.05 + 0.05 * (seed % 3);
    const auto rep = it::refine(T, opt);
    ASSERT_EQ(rep.reason, it::StopReason::Converged) << "seed " << seed << ": " << rep.message;
    EXPECT_EQ(rep.skipped_small_angle + rep.skipped_other, 0u) << "seed " << seed;
    EXPECT_EQ(delaunay_violation(T.mesh, 1e-9).second, 0u) << "seed " << seed;
    EXPECT_NEAR(T.mesh.total_area(), area, 1e-9 * area) << "seed " << seed;
    const double diag = bbox_diagonal(mesh);
    double worst = 0;
    for (int i = 0; i < 300; ++i) {
      auto q = random_input_point(T, rng);
      if (i % 3 == 0) q.bary = {q.bary[0] + q.bary[2], q.bary[1], 0.0};  // on an edge
      if (i % 10 == 0) q.bary = {0.0, 0.0, 1.0};                          // at a vertex
      const auto back = it::to_input(T, it::to_intrinsic(T, q));
      worst = std::max(worst, norm(sub(to3(it::input_position(T, back)), to3(it::input_position(T, q)))));
    }
    EXPECT_LE(worst, 1e-6 * diag) << "seed " << seed;
  }
}

}  // namespace
}  // namespace mtx
