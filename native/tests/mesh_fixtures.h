// mesh_fixtures.h — small procedural meshes with UV layouts for the Moldtex tests and
// benchmarks, plus geometric helpers that talk to the core only through moldtex.h.
//
// No GoogleTest here: the benchmark executable compiles this file too.
#ifndef MOLDTEX_TESTS_MESH_FIXTURES_H
#define MOLDTEX_TESTS_MESH_FIXTURES_H

#include <array>
#include <cmath>
#include <cstdint>
#include <functional>
#include <memory>
#include <vector>

#include "moldtex.h"

namespace mtx {

using Vec2 = std::array<double, 2>;
using Vec3 = std::array<double, 3>;

// Inline: the pattern measures call them for every pair of texels they compare.
inline Vec3 sub(const Vec3& a, const Vec3& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
inline Vec3 add(const Vec3& a, const Vec3& b) { return {a[0] + b[0], a[1] + b[1], a[2] + b[2]}; }
inline Vec3 scale(const Vec3& a, double s) { return {a[0] * s, a[1] * s, a[2] * s}; }
inline double dot(const Vec3& a, const Vec3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
inline Vec3 cross(const Vec3& a, const Vec3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
inline double norm(const Vec3& a) { return std::sqrt(dot(a, a)); }
inline Vec3 normalized(const Vec3& a) {
  const double n = norm(a);
  return n > 0 ? scale(a, 1.0 / n) : a;
}

// A triangle mesh with a UV layout, in the layout moldtex_mesh_desc wants.
struct Mesh {
  std::vector<float> positions;        // 3 floats per vertex
  std::vector<uint32_t> triangles;     // 3 vertex indices per triangle
  std::vector<float> uvs;              // 2 floats per UV
  std::vector<uint32_t> triangle_uvs;  // 3 UV indices per triangle; empty = per corner

  uint32_t vertex_count() const { return uint32_t(positions.size() / 3); }
  uint32_t triangle_count() const { return uint32_t(triangles.size() / 3); }
  // A descriptor pointing into this mesh (valid while the mesh lives unchanged).
  moldtex_mesh_desc desc() const;

  Vec3 vertex(uint32_t v) const;
  Vec3 corner(uint32_t t, int k) const;     // 3D position of corner k of triangle t
  Vec3 point(const moldtex_surface_point& p) const;  // 3D position of a surface point
  Vec2 corner_uv(uint32_t t, int k) const;  // UV of corner k of triangle t
  double area(uint32_t t) const;            // 3D area of triangle t
  double uv_area(uint32_t t) const;         // unsigned UV area of triangle t
  double signed_uv_area(uint32_t t) const;  // > 0 when the UV corners run counter-clockwise
  Vec3 normal(uint32_t t) const;            // unit normal (right-hand rule on the winding)
  double total_area() const;
  double total_uv_area() const;
};

// ---- generators ---------------------------------------------------------------------

using UvMap = std::function<Vec2(double x, double y)>;

// Grid in the z = 0 plane through the given x and y coordinates (strictly increasing),
// triangles wound counter-clockwise seen from +z, indexed UVs: uv = uv_of(x, y).
Mesh make_grid(const std::vector<double>& xs, const std::vector<double>& ys, const UvMap& uv_of);
// nx * ny cells over [x0, x1] x [y0, y1].
Mesh make_plane(int nx, int ny, double x0, double y0, double x1, double y1, const UvMap& uv_of);
// The unit quad [0,1]^2 at z = 0 as two triangles, UV = xy.
Mesh make_quad();
// A 4 x 4 plane ([0,4]^2, z = 0) of n x n quads whose UVs are warped u -> u^2, v = y / 4:
// a texel's 3D width is 2 / x mean texel lengths (over 2 left of x = 1, 6.7 at x = 0.3),
// its height one.
Mesh make_uv_squared_plane(int n);
// An 8 x 1 rectangle ([0,8] x [0,1], z = 0) in n*8 x n cells, squeezed into the unit UV
// square with a non-linear warp: u = (s + 3 s^3) / 4 with s = x / 8, v = (t + t^2) / 2
// with t = y. du/dx varies 10x across the plane and the 3D/UV aspect is 8:1.
// Injective (both maps are strictly increasing).
Mesh make_distorted_plane(int n);
// Strip [0,4] x [0,1]: region A (x < 1) in 8 x 8 cells, region B (x > 1) in 1 x 8 cells,
// so a B triangle has 24x the area of an A triangle. A takes u in [0, 0.5], B takes
// u in [0.5, 1]: spawning by index gives A ~ 0.89, by UV area ~ 0.5, by 3D area 0.25.
Mesh make_two_density_strip();
// The unit cube [-0.5, 0.5]^3: 8 shared vertices, 12 triangles, per-corner UVs laid out
// as a cross of 6 separate islands (each face inset in its own 1/4 x 1/4 cell, so each
// of the 12 cube edges is a UV seam and there is empty space between islands).
Mesh make_cube();
// Lat-long UV sphere: `segments` around z, `rings` bands from pole to pole, poles as
// triangle fans, per-corner UVs u = longitude / 2pi, v = latitude mapped to [0, 1];
// seam at longitude 0 and at the poles (each fan corner has its own pole UV).
Mesh make_uv_sphere(int segments, int rings, double radius);
// Torus around z: major radius R, minor radius r, nu segments along the major circle,
// nv along the minor circle; indexed UVs on an (nu+1) x (nv+1) grid (seams at u = 0
// and v = 0).
Mesh make_torus(int nu, int nv, double R, double r);
// Open cylinder around z (no caps: two boundary loops), radius, height in [0, height],
// indexed UVs (seam at angle 0).
Mesh make_open_cylinder(int segments, int rings, double radius, double height);
// Three triangles sharing the edge (v0, v1): refused as non-manifold.
Mesh make_nonmanifold_fan();
// A mesh from double positions, without UVs (the intrinsic code never reads them).
Mesh mesh_from(const std::vector<Vec3>& points, const std::vector<uint32_t>& triangles);
// Unit sphere from `rings` latitude bands and `n` segments, poles as fans; band r joins
// ring vertex j to vertex j + shift of the next ring, so with shift > 0 the bands are made
// of long twisted slivers (with obtuse angles). shift 0 is the ordinary UV sphere. No UVs.
Mesh make_twisted_sphere(int n, int rings, int shift);
// Per-corner UVs that give every triangle its own small island in a grid (a layout for
// meshes that have none, where the UV layout does not matter).
void give_atlas_uvs(Mesh& m);

// ---- geometry against a mesh --------------------------------------------------------

// Barycentric weights of the projection of p onto the plane of triangle t.
Vec3 barycentric(const Mesh& m, uint32_t t, const Vec3& p);
// Euclidean distance from p to triangle (a, b, c).
double point_triangle_distance(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c);
// Distance from p to the nearest triangle of the mesh (brute force with culling).
double distance_to_mesh(const Mesh& m, const Vec3& p);
// Precomputed bounding spheres for repeated distance_to_mesh queries on one mesh.
class SurfaceIndex {
 public:
  explicit SurfaceIndex(const Mesh& m);
  double distance(const Vec3& p) const;

 private:
  struct Tri {
    Vec3 a, b, c, centroid;
    double radius;
  };
  std::vector<Tri> tris_;
};
// Smallest distance from the origin to the plane of any triangle (inner radius of a
// polyhedral sphere centred at the origin).
double min_plane_distance_to_origin(const Mesh& m);
// The surface point of the mesh nearest to p (closest triangle, clamped barycentrics).
moldtex_surface_point locate(const Mesh& m, const Vec3& p);

// ---- handles --------------------------------------------------------------------------

struct SurfaceDeleter {
  void operator()(moldtex_surface_t* s) const { moldtex_surface_release(s); }
};
struct SimDeleter {
  void operator()(moldtex_sim_t* s) const { moldtex_sim_release(s); }
};
using SurfacePtr = std::unique_ptr<moldtex_surface_t, SurfaceDeleter>;
using SimPtr = std::unique_ptr<moldtex_sim_t, SimDeleter>;

// nullptr on failure (status in *status when given).
SurfacePtr create_surface(const Mesh& m, moldtex_status* status = nullptr);
moldtex_sim_params default_params();
// The continuous model's default agent with turnover (mean lifetime 0.5 s, activation
// time 0.2 s): a network that keeps its character from about 2 s on, with cells of a few
// tenths of a mesh unit (without turnover it keeps coarsening, Fig. 5).
moldtex_continuous_params turnover_look();
// Backend: MOLDTEX_BACKEND_CPU (not the AUTO default), so CPU tests stay CPU tests on
// machines with an OpenCL GPU. Set config.backend yourself to test another backend.
moldtex_sim_config make_config(uint32_t width, uint32_t height, uint32_t agents, uint64_t seed);
SimPtr create_sim(moldtex_surface surface, const moldtex_sim_config& config,
                  const moldtex_sim_params& params, moldtex_status* status = nullptr);

// Evaluates a surface point (NaNs if the call fails).
Vec3 evaluate_position(moldtex_surface s, const moldtex_surface_point& p);
Vec2 evaluate_uv(moldtex_surface s, const moldtex_surface_point& p);

// Result of moldtex_surface_trace with the whole path.
struct Trace {
  moldtex_status status = MOLDTEX_ERROR_INTERNAL;
  moldtex_surface_point end{};
  std::vector<Vec3> path;
  double path_length() const;
};
Trace trace(moldtex_surface s, const moldtex_surface_point& start, const Vec3& direction,
            double length);

std::vector<moldtex_surface_point> read_agents(moldtex_sim sim, uint32_t count);
std::vector<float> read_rgba(moldtex_sim sim, uint32_t width, uint32_t height);
std::vector<uint8_t> read_classes(moldtex_sim sim, uint32_t width, uint32_t height);
moldtex_sim_stats get_stats(moldtex_sim sim);

}  // namespace mtx

#endif  // MOLDTEX_TESTS_MESH_FIXTURES_H
