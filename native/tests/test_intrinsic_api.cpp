// The intrinsic Delaunay triangulation through the C API (issue 11): refusals with
// messages, the info numbers against the library called directly, and point location
// both ways (the 3D positions of a point and of its image must agree).
#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

#include "intrinsic/correspondence.h"
#include "intrinsic/refinement.h"
#include "test_util.h"

namespace mtx {
namespace {

struct IntrinsicDeleter {
  void operator()(moldtex_intrinsic_t* p) const { moldtex_intrinsic_release(p); }
};
using IntrinsicPtr = std::unique_ptr<moldtex_intrinsic_t, IntrinsicDeleter>;

moldtex_intrinsic_params Params(float bound) {
  moldtex_intrinsic_params p;
  moldtex_intrinsic_params_init(&p);
  p.max_circumradius = bound;
  return p;
}

IntrinsicPtr Create(moldtex_surface s, const moldtex_intrinsic_params& p, moldtex_status* status = nullptr) {
  moldtex_intrinsic out = nullptr;
  const moldtex_status st = moldtex_intrinsic_create(s, &p, &out);
  if (status) *status = st;
  else EXPECT_EQ(st, MOLDTEX_OK) << LastError();
  return IntrinsicPtr(out);
}

moldtex_intrinsic_info Info(moldtex_intrinsic h) {
  moldtex_intrinsic_info info;
  moldtex_intrinsic_info_init(&info);
  EXPECT_EQ(moldtex_intrinsic_get_info(h, &info), MOLDTEX_OK) << LastError();
  return info;
}

// Expects `status` and a message containing `words`.
void ExpectRefused(moldtex_status got, moldtex_status want, const std::string& words) {
  EXPECT_EQ(got, want) << LastError();
  EXPECT_NE(LastError().find(words), std::string::npos) << "message: " << LastError();
}

// Uniformly random points over the mesh's triangles (by area).
std::vector<moldtex_surface_point> RandomPoints(const Mesh& m, int n, uint32_t seed) {
  std::mt19937 rng(seed);
  std::vector<double> cdf(m.triangle_count());
  double acc = 0;
  for (uint32_t t = 0; t < m.triangle_count(); ++t) cdf[t] = acc += m.area(t);
  std::uniform_real_distribution<double> u(0, 1);
  std::vector<moldtex_surface_point> pts(n);
  for (auto& p : pts) {
    p.triangle = uint32_t(std::lower_bound(cdf.begin(), cdf.end(), u(rng) * acc) - cdf.begin());
    p.triangle = std::min(p.triangle, m.triangle_count() - 1);
    double a = u(rng), b = u(rng);
    if (a + b > 1) a = 1 - a, b = 1 - b;
    p.bary[0] = float(1 - a - b);
    p.bary[1] = float(a);
    p.bary[2] = float(b);
  }
  return pts;
}

TEST(IntrinsicApi, RefusesBadArguments) {
  const Mesh m = make_uv_sphere(16, 8, 1.0);
  SurfacePtr s = create_surface(m);
  ASSERT_TRUE(s);
  moldtex_intrinsic out = nullptr;
  moldtex_intrinsic_params p = Params(0.1f);
  ExpectRefused(moldtex_intrinsic_create(s.get(), &p, nullptr), MOLDTEX_ERROR_INVALID_ARGUMENT, "out_intrinsic");
  ExpectRefused(moldtex_intrinsic_create(nullptr, &p, &out), MOLDTEX_ERROR_INVALID_ARGUMENT, "surface handle");
  EXPECT_EQ(out, nullptr);
  ExpectRefused(moldtex_intrinsic_create(s.get(), nullptr, &out), MOLDTEX_ERROR_INVALID_ARGUMENT, "NULL");
  p.struct_size = 4;
  ExpectRefused(moldtex_intrinsic_create(s.get(), &p, &out), MOLDTEX_ERROR_INVALID_ARGUMENT, "struct_size");
  for (float bad : {std::nanf(""), -0.1f, std::numeric_limits<float>::infinity()}) {
    p = Params(bad);
    ExpectRefused(moldtex_intrinsic_create(s.get(), &p, &out), MOLDTEX_ERROR_INVALID_ARGUMENT, "max_circumradius");
    EXPECT_EQ(out, nullptr);
  }
  for (uint32_t cap : {0u, 16000001u}) {
    p = Params(0.1f);
    p.max_insertions = cap;
    ExpectRefused(moldtex_intrinsic_create(s.get(), &p, &out), MOLDTEX_ERROR_INVALID_ARGUMENT, "max_insertions");
  }
  // Area ~12.5 / 1e-8 = 1.25e9 vertices: refused before building, with the numbers.
  p = Params(1e-4f);
  ExpectRefused(moldtex_intrinsic_create(s.get(), &p, &out), MOLDTEX_ERROR_TOO_LARGE, "max_insertions (4000000)");
  EXPECT_NE(LastError().find("use a bound of at least"), std::string::npos) << LastError();
  EXPECT_EQ(out, nullptr);
  // A small cap stops refinement (not an error) and says so.
  p = Params(0.05f);
  p.max_insertions = 50000;
  IntrinsicPtr h = Create(s.get(), p);
  p.max_insertions = 100;
  ExpectRefused(moldtex_intrinsic_create(s.get(), &p, &out), MOLDTEX_ERROR_TOO_LARGE, "area / bound^2");

  // Info and points.
  ASSERT_TRUE(h);
  moldtex_intrinsic_info info;
  moldtex_intrinsic_info_init(&info);
  ExpectRefused(moldtex_intrinsic_get_info(nullptr, &info), MOLDTEX_ERROR_INVALID_ARGUMENT, "handle is NULL");
  ExpectRefused(moldtex_intrinsic_get_info(h.get(), nullptr), MOLDTEX_ERROR_INVALID_ARGUMENT, "NULL");
  info.struct_size = 8;
  ExpectRefused(moldtex_intrinsic_get_info(h.get(), &info), MOLDTEX_ERROR_INVALID_ARGUMENT, "struct_size");

  moldtex_surface_point in{0, {1.f / 3, 1.f / 3, 1.f / 3}}, res{};
  ExpectRefused(moldtex_intrinsic_locate(h.get(), nullptr, 1, &res), MOLDTEX_ERROR_INVALID_ARGUMENT, "NULL");
  ExpectRefused(moldtex_intrinsic_locate(h.get(), &in, 1, nullptr), MOLDTEX_ERROR_INVALID_ARGUMENT, "NULL");
  ExpectRefused(moldtex_intrinsic_locate(h.get(), &in, 0, &res), MOLDTEX_ERROR_INVALID_ARGUMENT, "count is 0");
  ExpectRefused(moldtex_intrinsic_locate(h.get(), &in, (1u << 24) + 1, &res), MOLDTEX_ERROR_TOO_LARGE,
                "at most 16,777,216");
  ExpectRefused(moldtex_intrinsic_locate(nullptr, &in, 1, &res), MOLDTEX_ERROR_INVALID_ARGUMENT, "handle is NULL");
  moldtex_surface_point bad = in;
  bad.triangle = m.triangle_count();
  ExpectRefused(moldtex_intrinsic_locate(h.get(), &bad, 1, &res), MOLDTEX_ERROR_INVALID_ARGUMENT, "out of range");
  bad = in;
  bad.bary[1] = std::nanf("");
  ExpectRefused(moldtex_intrinsic_locate(h.get(), &bad, 1, &res), MOLDTEX_ERROR_INVALID_ARGUMENT, "finite");
  bad = in;
  bad.bary[0] = 1.5f;
  ExpectRefused(moldtex_intrinsic_locate(h.get(), &bad, 1, &res), MOLDTEX_ERROR_INVALID_ARGUMENT, "sum to 1");
  bad = in;
  bad.triangle = Info(h.get()).triangle_count;
  ExpectRefused(moldtex_intrinsic_to_input(h.get(), &bad, 1, &res), MOLDTEX_ERROR_INVALID_ARGUMENT, "out of range");
  std::vector<moldtex_surface_point> few(3);
  ExpectRefused(moldtex_intrinsic_vertex_points(h.get(), few.data(), 3), MOLDTEX_ERROR_INVALID_ARGUMENT,
                "vertices");
  ExpectRefused(moldtex_intrinsic_vertex_points(h.get(), nullptr, 3), MOLDTEX_ERROR_INVALID_ARGUMENT, "NULL");
}

TEST(IntrinsicApi, FlipsOnlyKeepsTheInputVertices) {
  const Mesh m = make_uv_sphere(32, 16, 1.0);
  SurfacePtr s = create_surface(m);
  ASSERT_TRUE(s);
  IntrinsicPtr h = Create(s.get(), Params(0.f));
  ASSERT_TRUE(h);
  const moldtex_intrinsic_info info = Info(h.get());
  EXPECT_EQ(info.vertex_count, m.vertex_count());
  EXPECT_EQ(info.input_vertex_count, m.vertex_count());
  EXPECT_EQ(info.triangle_count, m.triangle_count());
  EXPECT_EQ(info.input_triangle_count, m.triangle_count());
  EXPECT_EQ(info.insertions + info.boundary_splits, 0u);
  EXPECT_EQ(info.stop_reason, MOLDTEX_INTRINSIC_STOP_CONVERGED);
  EXPECT_EQ(int64_t(info.vertex_count) - info.edge_count + info.triangle_count, 2);
  EXPECT_NEAR(info.area, m.total_area(), 1e-6 * m.total_area());
  EXPECT_GT(info.build_seconds, 0.0);
  EXPECT_NE(std::string(info.message).find("edge flips"), std::string::npos) << info.message;
  // The handle keeps working after its surface is released.
  s.reset();
  std::vector<moldtex_surface_point> vp(info.vertex_count), vi(info.vertex_count);
  ASSERT_EQ(moldtex_intrinsic_vertex_points(h.get(), vp.data(), info.vertex_count), MOLDTEX_OK) << LastError();
  ASSERT_EQ(moldtex_intrinsic_locate(h.get(), vp.data(), info.vertex_count, vi.data()), MOLDTEX_OK) << LastError();
  for (const auto& p : vi) EXPECT_TRUE(ValidPoint(p, info.triangle_count));
}

TEST(IntrinsicApi, InfoMatchesTheLibrary) {
  // Closed (sphere) and open (cylinder: boundary splits) surfaces.
  for (const Mesh& m : {make_uv_sphere(64, 32, 1.0), make_open_cylinder(24, 6, 0.5, 2.0)}) {
    SurfacePtr s = create_surface(m);
    ASSERT_TRUE(s);
    const float bound = 0.04f;
    IntrinsicPtr h = Create(s.get(), Params(bound));
    ASSERT_TRUE(h);
    const moldtex_intrinsic_info info = Info(h.get());

    namespace it = moldtex::intrinsic;
    it::IntrinsicTriangulation T = it::build_intrinsic_triangulation(
        std::vector<double>(m.positions.begin(), m.positions.end()), m.triangles);
    it::RefineOptions o;
    o.max_circumradius = bound;
    o.max_insertions = 4000000;
    const it::RefineReport r = it::refine(T, o);
    EXPECT_EQ(info.vertex_count, T.mesh.vertex_count());
    EXPECT_EQ(info.triangle_count, T.mesh.face_count());
    EXPECT_EQ(info.edge_count, T.mesh.edge_count());
    EXPECT_EQ(info.insertions, r.insertions);
    EXPECT_EQ(info.boundary_splits, r.boundary_splits);
    EXPECT_EQ(info.flips, r.flips);
    EXPECT_EQ(info.faces_over_bound_sharp, r.skipped_small_angle);
    EXPECT_EQ(info.faces_over_bound_other, r.skipped_other);
    EXPECT_EQ(std::string(info.message), r.message.substr(0, 255));
    EXPECT_EQ(info.vertex_count, m.vertex_count() + info.insertions + info.boundary_splits);
    EXPECT_EQ(info.stop_reason, MOLDTEX_INTRINSIC_STOP_CONVERGED) << info.message;
    EXPECT_DOUBLE_EQ(info.max_circumradius, double(bound));
    if (info.faces_over_bound_sharp + info.faces_over_bound_other == 0) {
      EXPECT_LE(info.largest_circumradius, double(bound) * (1 + 1e-9));
    }
    // Chew: about 0.4 .. 1.6 area / bound^2 vertices.
    const double expected = m.total_area() / (double(bound) * bound);
    EXPECT_GT(info.vertex_count, 0.3 * expected);
    EXPECT_LT(info.vertex_count, 2.0 * expected);
    std::printf("[ figures  ] %u input vertices -> %u vertices (area/bound^2 = %.0f), %llu flips, %llu insertions, "
                "%llu boundary splits, %.3f s\n",
                m.vertex_count(), info.vertex_count, expected, (unsigned long long)info.flips,
                (unsigned long long)info.insertions, (unsigned long long)info.boundary_splits, info.build_seconds);
  }
}

TEST(IntrinsicApi, LocateRoundTripKeepsThe3DPosition) {
  const Mesh m = make_torus(48, 24, 1.0, 0.35);
  SurfacePtr s = create_surface(m);
  ASSERT_TRUE(s);
  IntrinsicPtr h = Create(s.get(), Params(0.03f));
  ASSERT_TRUE(h);
  const moldtex_intrinsic_info info = Info(h.get());
  EXPECT_GT(info.insertions, 0u);

  // Input -> intrinsic -> input.
  const std::vector<moldtex_surface_point> pts = RandomPoints(m, 2000, 7);
  std::vector<moldtex_surface_point> in_intr(pts.size()), back(pts.size());
  ASSERT_EQ(moldtex_intrinsic_locate(h.get(), pts.data(), uint32_t(pts.size()), in_intr.data()), MOLDTEX_OK)
      << LastError();
  ASSERT_EQ(moldtex_intrinsic_to_input(h.get(), in_intr.data(), uint32_t(pts.size()), back.data()), MOLDTEX_OK)
      << LastError();
  double worst = 0;
  for (size_t i = 0; i < pts.size(); ++i) {
    ASSERT_TRUE(ValidPoint(in_intr[i], info.triangle_count));
    ASSERT_TRUE(ValidPoint(back[i], m.triangle_count()));
    worst = std::max(worst, norm(sub(evaluate_position(s.get(), pts[i]), evaluate_position(s.get(), back[i]))));
  }
  std::printf("[ figures  ] locate round trip: largest 3D error %.3g (torus, minor radius 0.35)\n", worst);
  EXPECT_LT(worst, 1e-4);

  // Vertex points: locate each; it must land on a corner of an intrinsic triangle, and
  // mapping back gives the same 3D position.
  std::vector<moldtex_surface_point> vp(info.vertex_count);
  ASSERT_EQ(moldtex_intrinsic_vertex_points(h.get(), vp.data(), uint32_t(vp.size())), MOLDTEX_OK) << LastError();
  for (const auto& p : vp) ASSERT_TRUE(ValidPoint(p, m.triangle_count()));
  std::vector<moldtex_surface_point> vi(vp.size()), vb(vp.size());
  ASSERT_EQ(moldtex_intrinsic_locate(h.get(), vp.data(), uint32_t(vp.size()), vi.data()), MOLDTEX_OK) << LastError();
  ASSERT_EQ(moldtex_intrinsic_to_input(h.get(), vi.data(), uint32_t(vi.size()), vb.data()), MOLDTEX_OK)
      << LastError();
  double worst_v = 0, least_corner = 1;
  for (size_t v = 0; v < vp.size(); ++v) {
    least_corner = std::min(least_corner, double(*std::max_element(vi[v].bary, vi[v].bary + 3)));
    worst_v = std::max(worst_v, norm(sub(evaluate_position(s.get(), vp[v]), evaluate_position(s.get(), vb[v]))));
  }
  EXPECT_GT(least_corner, 1 - 1e-4);
  EXPECT_LT(worst_v, 1e-4);
}

TEST(IntrinsicApi, UnusedVerticesAndDroppedTriangles) {
  // The quad plus a triangle repeating a vertex index and an unused vertex.
  Mesh m = make_quad();
  m.positions.insert(m.positions.end(), {2.f, 2.f, 0.f});
  m.triangles.insert(m.triangles.end(), {0, 1, 1});
  m.triangle_uvs.insert(m.triangle_uvs.end(), {0, 1, 1});
  SurfacePtr s = create_surface(m);
  ASSERT_TRUE(s) << LastError();
  IntrinsicPtr h = Create(s.get(), Params(0.2f));
  ASSERT_TRUE(h);
  const moldtex_intrinsic_info info = Info(h.get());
  EXPECT_EQ(info.dropped_triangle_count, 1u);
  EXPECT_EQ(info.input_triangle_count, 2u);
  std::vector<moldtex_surface_point> vp(info.vertex_count);
  ASSERT_EQ(moldtex_intrinsic_vertex_points(h.get(), vp.data(), uint32_t(vp.size())), MOLDTEX_OK) << LastError();
  EXPECT_EQ(vp[4].triangle, MOLDTEX_INTRINSIC_NO_TRIANGLE);
  moldtex_surface_point p{2, {0.2f, 0.4f, 0.4f}}, r{};
  ExpectRefused(moldtex_intrinsic_locate(h.get(), &p, 1, &r), MOLDTEX_ERROR_INVALID_ARGUMENT,
                "repeats a vertex index");
}

}  // namespace
}  // namespace mtx
