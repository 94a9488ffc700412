// Surface map tools (issue 12, Layton et al. §6, Fig. 14-17): heat-method geodesic
// distance, Laplace interpolation, short-time diffusion and the per-triangle gradient,
// through the C API. The reference quantities (exact great-circle distances, a cotangent
// Laplacian and a barycentric mass written here independently of the core) live in this
// file, so the checks do not reuse the code they check.
#include <algorithm>
#include <cmath>
#include <numeric>
#include <map>
#include <random>

#include "test_util.h"

namespace mtx {
namespace {

constexpr double kPi = 3.14159265358979323846;

std::vector<float> Geodesic(moldtex_surface s, const std::vector<float>& weights, float factor = 1.f,
                            moldtex_status* status = nullptr) {
  std::vector<float> out(weights.size(), std::nanf(""));
  const moldtex_status st =
      moldtex_surface_geodesic_distance(s, weights.data(), weights.size(), factor, out.data(), out.size());
  if (status) *status = st;
  else EXPECT_EQ(st, MOLDTEX_OK) << LastError();
  return out;
}

// Independent reference: the cotangent weights w_ij = (cot a + cot b) / 2 of each edge and
// the barycentric mass (a third of each triangle's area per corner).
struct Reference {
  std::vector<std::vector<std::pair<uint32_t, double>>> edges;  // per vertex: (neighbour, w)
  std::vector<double> mass;
  explicit Reference(const Mesh& m) : edges(m.vertex_count()), mass(m.vertex_count(), 0.0) {
    for (uint32_t t = 0; t < m.triangle_count(); ++t) {
      for (int c = 0; c < 3; ++c) {
        const Vec3 a = sub(m.corner(t, (c + 1) % 3), m.corner(t, c));
        const Vec3 b = sub(m.corner(t, (c + 2) % 3), m.corner(t, c));
        const double cot = dot(a, b) / norm(cross(a, b));
        const uint32_t i = m.triangles[3 * t + (c + 1) % 3], j = m.triangles[3 * t + (c + 2) % 3];
        edges[i].push_back({j, 0.5 * cot});
        edges[j].push_back({i, 0.5 * cot});
        mass[m.triangles[3 * t + c]] += m.area(t) / 3.0;
      }
    }
  }
  // (L x)_i = sum_j w_ij (x_i - x_j); also the scale sum_j |w_ij| (|x_i| + |x_j|).
  double apply(uint32_t i, const std::vector<float>& x, double* scale) const {
    double r = 0, sc = 0;
    for (auto [j, w] : edges[i]) {
      r += w * (double(x[i]) - x[j]);
      sc += std::fabs(w) * (std::fabs(x[i]) + std::fabs(x[j]));
    }
    if (scale) *scale = sc;
    return r;
  }
};

// Icosphere of radius 1: an icosahedron with each triangle split in four `levels` times,
// vertices pushed onto the sphere. UVs per corner from the x, y of the position (any
// layout will do: the map tools work on 3D positions only).
Mesh Icosphere(int levels) {
  const double g = (1 + std::sqrt(5.0)) / 2;
  std::vector<Vec3> p = {{-1, g, 0}, {1, g, 0}, {-1, -g, 0}, {1, -g, 0}, {0, -1, g}, {0, 1, g},
                         {0, -1, -g}, {0, 1, -g}, {g, 0, -1}, {g, 0, 1}, {-g, 0, -1}, {-g, 0, 1}};
  std::vector<uint32_t> t = {0, 11, 5, 0, 5, 1, 0, 1, 7, 0, 7, 10, 0, 10, 11, 1, 5, 9, 5, 11, 4, 11, 10, 2,
                             10, 7, 6, 7, 1, 8, 3, 9, 4, 3, 4, 2, 3, 2, 6, 3, 6, 8, 3, 8, 9, 4, 9, 5,
                             2, 4, 11, 6, 2, 10, 8, 6, 7, 9, 8, 1};
  for (Vec3& v : p) v = normalized(v);
  for (int l = 0; l < levels; ++l) {
    std::map<std::pair<uint32_t, uint32_t>, uint32_t> mid;
    auto middle = [&](uint32_t a, uint32_t b) {
      const auto key = std::minmax(a, b);
      auto it = mid.find(key);
      if (it != mid.end()) return it->second;
      p.push_back(normalized(scale(add(p[a], p[b]), 0.5)));
      return mid[key] = uint32_t(p.size() - 1);
    };
    std::vector<uint32_t> next;
    for (size_t i = 0; i < t.size(); i += 3) {
      const uint32_t a = t[i], b = t[i + 1], c = t[i + 2];
      const uint32_t ab = middle(a, b), bc = middle(b, c), ca = middle(c, a);
      next.insert(next.end(), {a, ab, ca, b, bc, ab, c, ca, bc, ab, bc, ca});
    }
    t.swap(next);
  }
  Mesh m;
  for (const Vec3& v : p)
    for (double c : v) m.positions.push_back(float(c));
  m.triangles = t;
  for (uint32_t v : t) {
    m.uvs.push_back(float(0.5 + 0.45 * p[v][0]));
    m.uvs.push_back(float(0.5 + 0.45 * p[v][1]));
  }
  return m;
}

// The UV sphere's vertex nearest the +x axis on the equator (rings even).
uint32_t EquatorVertex(const Mesh& m) {
  uint32_t best = 0;
  double best_d = 1e9;
  for (uint32_t v = 0; v < m.vertex_count(); ++v) {
    const double d = norm(sub(m.vertex(v), Vec3{1, 0, 0}));
    if (d < best_d) best_d = d, best = v;
  }
  return best;
}

// Mean and max relative error of the heat-method distance from vertex `src` against the
// great-circle distance on the unit sphere, over vertices farther than 0.2 from it.
void SphereError(const Mesh& m, uint32_t src, double* mean, double* max) {
  auto s = create_surface(m);
  ASSERT_TRUE(s) << LastError();
  std::vector<float> w(m.vertex_count(), 0.f);
  w[src] = 1.f;
  const std::vector<float> d = Geodesic(s.get(), w);
  EXPECT_EQ(d[src], 0.f);
  double sum = 0, worst = 0;
  int n = 0;
  const Vec3 p = normalized(m.vertex(src));
  for (uint32_t v = 0; v < m.vertex_count(); ++v) {
    const double exact = std::acos(std::clamp(dot(p, normalized(m.vertex(v))), -1.0, 1.0));
    ASSERT_TRUE(std::isfinite(d[v]) && d[v] >= 0.f) << "vertex " << v << ": " << d[v];
    if (exact < 0.2) continue;
    const double rel = std::fabs(d[v] - exact) / exact;
    sum += rel;
    worst = std::max(worst, rel);
    ++n;
  }
  *mean = sum / n;
  *max = worst;
}

TEST(SurfaceMaps, HeatGeodesicOnASphereMatchesGreatCircles) {
  // Issue 12's check: mean relative error <= 2 % over the vertices farther than 0.2
  // radius from a point source (a vertex), against the great-circle distance.
  //  - Icosphere, 2562 vertices (edges ~0.08): measured ~1.0 %. The heat method's error
  //    is largest near the source and the cut locus and falls with the edge length: the
  //    10242-vertex icosphere must do better (measured ~0.65 %).
  //  - 64 x 32 UV sphere from the pole: the mesh is symmetric about the source, so the
  //    distance is nearly exact (measured ~0.1 %), bound 2 %.
  //  - The same UV sphere from an equator vertex: measured ~1.97 %, bound 2.5 %. Its
  //    short edges near the poles pull the mean edge length h (so t = h^2) below the
  //    spacing around the source, which Crane et al.'s t assumes; the add-on's time
  //    factor raises t (2 gives ~1.4 % there).
  double mean = 0, max = 0, finer = 0;
  SphereError(Icosphere(4), 0, &mean, &max);
  std::printf("geodesic on the 2562-vertex icosphere: mean relative error %.4f, max %.4f\n", mean, max);
  RecordProperty("icosphere_mean_relative_error", std::to_string(mean));
  EXPECT_LE(mean, 0.02);
  SphereError(Icosphere(5), 0, &finer, &max);
  std::printf("geodesic on the 10242-vertex icosphere: mean relative error %.4f, max %.4f\n", finer, max);
  EXPECT_LT(finer, mean);
  const Mesh m = make_uv_sphere(64, 32, 1.0);
  SphereError(m, 0, &mean, &max);  // the north pole
  std::printf("geodesic on the UV sphere from the pole: mean relative error %.4f, max %.4f\n", mean, max);
  EXPECT_LE(mean, 0.02);
  SphereError(m, EquatorVertex(m), &mean, &max);
  std::printf("geodesic on the UV sphere from the equator: mean relative error %.4f, max %.4f\n", mean, max);
  EXPECT_LE(mean, 0.025);
}

TEST(SurfaceMaps, HeatGeodesicFromARegionAndUnreachableComponents) {
  // A plane strip [0,4] x [0,1] beside a second, disconnected quad. Source: the left edge
  // (x = 0). On a plane the distance from a straight edge is x itself. The heat method's
  // error there comes from the grid's diagonals and the boundary (Neumann) heat flow: it
  // is largest along the long edges next to the source (measured max 0.028, mean ~0.013):
  // bounds 0.5 % (mean) and 1 % (max) of the strip's length 4. The other component
  // has no source: -1 (documented), never NaN.
  Mesh m = make_plane(32, 8, 0, 0, 4, 1, [](double x, double y) { return Vec2{x / 8, y / 2}; });
  const uint32_t base = m.vertex_count();
  const float extra[] = {10, 0, 0, 11, 0, 0, 11, 1, 0, 10, 1, 0};
  m.positions.insert(m.positions.end(), extra, extra + 12);
  const float extra_uv[] = {0.6f, 0.6f, 0.9f, 0.6f, 0.9f, 0.9f, 0.6f, 0.9f};
  m.uvs.insert(m.uvs.end(), extra_uv, extra_uv + 8);
  for (uint32_t k : {0u, 1u, 2u, 0u, 2u, 3u}) m.triangles.push_back(base + k);
  m.triangle_uvs = m.triangles;
  auto s = create_surface(m);
  ASSERT_TRUE(s) << LastError();
  std::vector<float> w(m.vertex_count(), 0.f);
  for (uint32_t v = 0; v < base; ++v)
    if (m.vertex(v)[0] < 1e-9) w[v] = 0.9f;
  const std::vector<float> d = Geodesic(s.get(), w);
  double worst = 0;
  double sum = 0;
  for (uint32_t v = 0; v < base; ++v) {
    const double e = std::fabs(d[v] - m.vertex(v)[0]);
    worst = std::max(worst, e);
    sum += e;
  }
  std::printf("distance from the strip's edge: mean abs error %.5f, max %.5f (strip length 4)\n", sum / base, worst);
  EXPECT_LT(sum / base, 0.02);
  EXPECT_LT(worst, 0.04);
  for (uint32_t v = base; v < m.vertex_count(); ++v) EXPECT_EQ(d[v], -1.f) << v;
}

TEST(SurfaceMaps, LaplaceHitsFixedValuesAndIsHarmonic) {
  // Torus (closed, curved, non-uniform cotangent weights) with random fixed vertices
  // (one in five) holding random values in [-1, 2]. Fixed values come back exactly
  // (1e-6: the only change is float -> double -> float). On free vertices the residual of
  // the independent cotangent Laplacian is ~0 relative to its own scale
  // sum_j |w_ij| (|x_i| + |x_j|): the solve is double precision, the result is rounded
  // to float (relative 6e-8 per entry), hence the 1e-5 bound.
  const Mesh m = make_torus(48, 24, 1.0, 0.35);
  auto s = create_surface(m);
  ASSERT_TRUE(s) << LastError();
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> value(-1.f, 2.f);
  std::vector<float> x0(m.vertex_count(), 0.f);
  std::vector<uint8_t> fixed(m.vertex_count(), 0);
  for (uint32_t v = 0; v < m.vertex_count(); ++v) {
    x0[v] = value(rng);
    fixed[v] = rng() % 5 == 0;
  }
  std::vector<float> x(m.vertex_count());
  ASSERT_EQ(moldtex_surface_laplace_interpolate(s.get(), x0.data(), fixed.data(), x0.size(), x.data(), x.size()),
            MOLDTEX_OK)
      << LastError();
  const Reference ref(m);
  double worst = 0;
  for (uint32_t v = 0; v < m.vertex_count(); ++v) {
    if (fixed[v]) {
      EXPECT_NEAR(x[v], x0[v], 1e-6) << v;
      continue;
    }
    double scale = 0;
    const double r = ref.apply(v, x, &scale);
    worst = std::max(worst, std::fabs(r) / scale);
  }
  std::printf("Laplace interpolation: worst relative residual %.3g\n", worst);
  EXPECT_LT(worst, 1e-5);
}

TEST(SurfaceMaps, LaplaceOnAPlaneStripIsLinear) {
  // 0 on the left edge, 1 on the right edge of an irregular planar strip [0,4] x [0,1]:
  // linear functions are harmonic and the cotangent Laplacian reproduces them exactly on
  // any planar triangulation, so the result is x / 4 up to rounding (1e-4).
  std::vector<double> xs = {0}, ys = {0};
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> step(0.05, 0.25);
  while (xs.back() < 3.8) xs.push_back(xs.back() + step(rng));
  xs.push_back(4);
  while (ys.back() < 0.8) ys.push_back(ys.back() + step(rng));
  ys.push_back(1);
  const Mesh m = make_grid(xs, ys, [](double x, double y) { return Vec2{x / 4, y}; });
  auto s = create_surface(m);
  ASSERT_TRUE(s) << LastError();
  std::vector<float> x0(m.vertex_count(), 0.f), x(m.vertex_count());
  std::vector<uint8_t> fixed(m.vertex_count(), 0);
  for (uint32_t v = 0; v < m.vertex_count(); ++v) {
    const double px = m.vertex(v)[0];
    if (px < 1e-9) fixed[v] = 1, x0[v] = 0.f;
    if (px > 4 - 1e-9) fixed[v] = 1, x0[v] = 1.f;
  }
  ASSERT_EQ(moldtex_surface_laplace_interpolate(s.get(), x0.data(), fixed.data(), x0.size(), x.data(), x.size()),
            MOLDTEX_OK)
      << LastError();
  double worst = 0;
  for (uint32_t v = 0; v < m.vertex_count(); ++v) worst = std::max(worst, std::fabs(x[v] - m.vertex(v)[0] / 4));
  std::printf("Laplace on the strip: max error vs x / 4: %.3g\n", worst);
  EXPECT_LT(worst, 1e-4);
}

TEST(SurfaceMaps, GradientOfALinearFunctionIsExact) {
  // An irregular grid (uneven spacing, jittered interior vertices) rotated into a tilted
  // plane; f(p) = a . p + c. The piecewise-linear gradient of a linear function is exact:
  // the projection of a onto the plane, in every triangle. Tolerance 1e-5 relative to
  // |a|: positions and values pass through float.
  std::vector<double> xs = {0}, ys = {0};
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> step(0.04, 0.2), jitter(-0.015, 0.015);
  while (xs.back() < 1.8) xs.push_back(xs.back() + step(rng));
  while (ys.back() < 0.9) ys.push_back(ys.back() + step(rng));
  Mesh m = make_grid(xs, ys, [](double x, double y) { return Vec2{x / 2, y}; });
  const Vec3 n = normalized(Vec3{0.3, -0.5, 0.8});
  const Vec3 e1 = normalized(cross(n, Vec3{0, 0, 1}));
  const Vec3 e2 = cross(n, e1);
  for (uint32_t v = 0; v < m.vertex_count(); ++v) {
    double x = m.positions[3 * v], y = m.positions[3 * v + 1];
    x += jitter(rng);
    y += jitter(rng);
    const Vec3 p = add(add(scale(e1, x), scale(e2, y)), Vec3{0.5, -0.25, 2.0});
    for (int k = 0; k < 3; ++k) m.positions[3 * v + k] = float(p[k]);
  }
  auto s = create_surface(m);
  ASSERT_TRUE(s) << LastError();
  const Vec3 a{1.5, -2.0, 0.75};
  std::vector<float> f(m.vertex_count());
  for (uint32_t v = 0; v < m.vertex_count(); ++v) f[v] = float(dot(a, m.vertex(v)) + 0.3);
  std::vector<float> g(3 * m.triangle_count());
  ASSERT_EQ(moldtex_surface_map_gradient(s.get(), f.data(), f.size(), g.data(), g.size()), MOLDTEX_OK)
      << LastError();
  double worst = 0;
  for (uint32_t t = 0; t < m.triangle_count(); ++t) {
    const Vec3 tn = m.normal(t);
    const Vec3 expected = sub(a, scale(tn, dot(a, tn)));
    worst = std::max(worst, norm(sub(Vec3{g[3 * t], g[3 * t + 1], g[3 * t + 2]}, expected)) / norm(a));
  }
  std::printf("gradient of a linear function: worst relative error %.3g\n", worst);
  EXPECT_LT(worst, 1e-5);

  // The gradient is accepted as a bias field as it is.
  moldtex_sim_config c = make_config(32, 32, 100, 1);
  c.model = MOLDTEX_MODEL_CONTINUOUS;
  auto sim = create_sim(s.get(), c, default_params());
  ASSERT_TRUE(sim) << LastError();
  EXPECT_EQ(moldtex_sim_set_bias(sim.get(), g.data(), g.size()), MOLDTEX_OK) << LastError();
}

TEST(SurfaceMaps, DiffusionConservesMassAndSmooths) {
  // Random values on a UV sphere. Backward Euler with the cotangent stiffness conserves
  // sum_i M_i x_i exactly (K's columns sum to 0): 1e-5 relative allows float rounding of
  // 2000 values. It lowers the M-weighted variance (an energy estimate; for t = r^2 / 2
  // with r = 0.2 noise at the edge scale, ~0.1, drops by far more than half: bound 0.5).
  // A tiny time (1e-6 h^2) changes nothing beyond 1e-4 (relative to the values' range 1).
  const Mesh m = make_uv_sphere(48, 24, 1.0);
  auto s = create_surface(m);
  ASSERT_TRUE(s) << LastError();
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> value(0.f, 1.f);
  std::vector<float> x0(m.vertex_count()), x(m.vertex_count());
  for (float& v : x0) v = value(rng);
  const Reference ref(m);
  auto integral = [&](const std::vector<float>& y) {
    double sum = 0;
    for (uint32_t v = 0; v < y.size(); ++v) sum += ref.mass[v] * y[v];
    return sum;
  };
  auto variance = [&](const std::vector<float>& y) {
    const double area = std::accumulate(ref.mass.begin(), ref.mass.end(), 0.0), mean = integral(y) / area;
    double sum = 0;
    for (uint32_t v = 0; v < y.size(); ++v) sum += ref.mass[v] * (y[v] - mean) * (y[v] - mean);
    return sum / area;
  };
  const float r = 0.2f;
  ASSERT_EQ(moldtex_surface_diffuse_map(s.get(), x0.data(), x0.size(), r * r / 2, x.data(), x.size()), MOLDTEX_OK)
      << LastError();
  const double i0 = integral(x0), i1 = integral(x);
  std::printf("diffusion: integral %.7f -> %.7f, variance %.5f -> %.5f\n", i0, i1, variance(x0), variance(x));
  EXPECT_NEAR(i1, i0, 1e-5 * std::fabs(i0));
  EXPECT_LT(variance(x), 0.5 * variance(x0));
  ASSERT_EQ(moldtex_surface_diffuse_map(s.get(), x0.data(), x0.size(), 1e-8f, x.data(), x.size()), MOLDTEX_OK);
  for (uint32_t v = 0; v < x.size(); ++v) EXPECT_NEAR(x[v], x0[v], 1e-4) << v;
  // A huge time: every value is the mean (clamped time, still finite).
  ASSERT_EQ(moldtex_surface_diffuse_map(s.get(), x0.data(), x0.size(), 1e30f, x.data(), x.size()), MOLDTEX_OK);
  const double mean = i0 / std::accumulate(ref.mass.begin(), ref.mass.end(), 0.0);
  for (uint32_t v = 0; v < x.size(); ++v) EXPECT_NEAR(x[v], mean, 1e-3) << v;
}

TEST(SurfaceMaps, DegenerateTrianglesAndUnusedVerticesStayFinite) {
  // A quad strip with a zero-area triangle (three collinear vertices) and a vertex no
  // triangle uses: every tool answers finite values; the unused vertex gets 0 (distance:
  // -1, unreachable) and the degenerate triangle a zero gradient.
  Mesh m = make_plane(4, 2, 0, 0, 2, 1, [](double x, double y) { return Vec2{x / 2, y}; });
  const uint32_t a = 0, b = 1, c = 2;  // (0,0), (0.5,0), (1,0): collinear
  m.triangles.insert(m.triangles.end(), {a, c, b});
  const float lone[] = {5, 5, 5};
  m.positions.insert(m.positions.end(), lone, lone + 3);
  m.uvs.insert(m.uvs.end(), {0.f, 0.f});
  m.triangle_uvs = m.triangles;
  auto s = create_surface(m);
  ASSERT_TRUE(s) << LastError();
  const uint32_t n = m.vertex_count(), lone_v = n - 1;
  std::vector<float> w(n, 0.f), out(n), g(3 * m.triangle_count());
  w[0] = 1.f;
  w[lone_v] = 0.7f;  // an unused vertex that is marked as a source measures 0
  const std::vector<float> d = Geodesic(s.get(), w);
  for (float v : d) EXPECT_TRUE(std::isfinite(v));
  EXPECT_EQ(d[lone_v], 0.f);
  w[lone_v] = 0.f;
  EXPECT_EQ(Geodesic(s.get(), w)[lone_v], -1.f);
  std::vector<float> values(n);
  for (uint32_t v = 0; v < n; ++v) values[v] = float(v % 3);
  std::vector<uint8_t> fixed(n, 0);
  fixed[0] = fixed[n - 2] = 1;
  ASSERT_EQ(moldtex_surface_laplace_interpolate(s.get(), values.data(), fixed.data(), n, out.data(), n), MOLDTEX_OK);
  for (float v : out) EXPECT_TRUE(std::isfinite(v));
  EXPECT_EQ(out[lone_v], 0.f);
  ASSERT_EQ(moldtex_surface_diffuse_map(s.get(), values.data(), n, 0.1f, out.data(), n), MOLDTEX_OK);
  for (float v : out) EXPECT_TRUE(std::isfinite(v));
  EXPECT_EQ(out[lone_v], 0.f);
  ASSERT_EQ(moldtex_surface_map_gradient(s.get(), values.data(), n, g.data(), g.size()), MOLDTEX_OK);
  for (float v : g) EXPECT_TRUE(std::isfinite(v));
  const uint32_t last = m.triangle_count() - 1;
  EXPECT_EQ(g[3 * last], 0.f);
  EXPECT_EQ(g[3 * last + 1], 0.f);
  EXPECT_EQ(g[3 * last + 2], 0.f);
}

TEST(SurfaceMaps, BadInputsAreRefusedWithAMessage) {
  const Mesh m = make_plane(4, 4, 0, 0, 1, 1, [](double x, double y) { return Vec2{x, y}; });
  auto s = create_surface(m);
  ASSERT_TRUE(s) << LastError();
  const size_t n = m.vertex_count(), nt = m.triangle_count();
  std::vector<float> v(n, 0.f), out(n, 7.f), g(3 * nt);
  v[0] = 1.f;
  std::vector<uint8_t> fixed(n, 0);
  fixed[0] = 1;
  auto refused = [&](moldtex_status st, const char* what) {
    EXPECT_EQ(st, MOLDTEX_ERROR_INVALID_ARGUMENT) << what;
    EXPECT_FALSE(LastError().empty()) << what;
  };
  refused(moldtex_surface_geodesic_distance(nullptr, v.data(), n, 1.f, out.data(), n), "NULL surface");
  refused(moldtex_surface_geodesic_distance(s.get(), nullptr, n, 1.f, out.data(), n), "NULL weights");
  refused(moldtex_surface_geodesic_distance(s.get(), v.data(), n - 1, 1.f, out.data(), n), "short weights");
  refused(moldtex_surface_geodesic_distance(s.get(), v.data(), n, 1.f, out.data(), n - 1), "short output");
  refused(moldtex_surface_geodesic_distance(s.get(), v.data(), n, 1.f, nullptr, n), "NULL output");
  refused(moldtex_surface_geodesic_distance(s.get(), v.data(), n, std::nanf(""), out.data(), n), "NaN factor");
  refused(moldtex_surface_geodesic_distance(s.get(), v.data(), n, 0.f, out.data(), n), "zero factor");
  std::vector<float> none(n, 0.2f);
  refused(moldtex_surface_geodesic_distance(s.get(), none.data(), n, 1.f, out.data(), n), "no source");
  EXPECT_NE(LastError().find("source"), std::string::npos) << LastError();
  std::vector<float> bad(v);
  bad[3] = std::nanf("");
  refused(moldtex_surface_geodesic_distance(s.get(), bad.data(), n, 1.f, out.data(), n), "NaN weight");
  EXPECT_NE(LastError().find("vertex 3"), std::string::npos) << LastError();
  refused(moldtex_surface_laplace_interpolate(s.get(), bad.data(), fixed.data(), n, out.data(), n), "NaN value");
  refused(moldtex_surface_laplace_interpolate(s.get(), v.data(), nullptr, n, out.data(), n), "NULL mask");
  std::vector<uint8_t> no_fixed(n, 0);
  refused(moldtex_surface_laplace_interpolate(s.get(), v.data(), no_fixed.data(), n, out.data(), n), "no fixed");
  refused(moldtex_surface_diffuse_map(s.get(), v.data(), n, -1.f, out.data(), n), "negative time");
  refused(moldtex_surface_diffuse_map(s.get(), v.data(), n, INFINITY, out.data(), n), "infinite time");
  refused(moldtex_surface_diffuse_map(s.get(), bad.data(), n, 1.f, out.data(), n), "NaN value");
  refused(moldtex_surface_diffuse_map(s.get(), v.data(), n + 1, 1.f, out.data(), n + 1), "long values");
  refused(moldtex_surface_map_gradient(s.get(), v.data(), n, g.data(), g.size() - 1), "short gradient");
  refused(moldtex_surface_map_gradient(s.get(), bad.data(), n, g.data(), g.size()), "NaN value");
  std::vector<float> huge(v);
  huge[1] = 1e20f;
  refused(moldtex_surface_map_gradient(s.get(), huge.data(), n, g.data(), g.size()), "huge value");
  for (float o : out) EXPECT_EQ(o, 7.f) << "a failed call wrote its output";
}

}  // namespace
}  // namespace mtx
