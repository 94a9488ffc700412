#include "surface/surface.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <unordered_map>

#include "common/error.h"
#include "surface/triangle_atlas.h"
#include "surface/unfolded_neighbours.h"

namespace moldtex {

namespace {

struct V3 {
  double x, y, z;
};
V3 sub(V3 a, V3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
double dot(V3 a, V3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
V3 cross(V3 a, V3 b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }
double norm(V3 a) { return std::sqrt(dot(a, a)); }

V3 vertex(const Surface& s, uint32_t v) {
  return {s.positions[3 * v], s.positions[3 * v + 1], s.positions[3 * v + 2]};
}


// UV islands: triangles joined by shared edges that are not seams (union-find).
void label_islands(Surface& s) {
  const uint32_t nt = s.triangle_count();
  std::vector<uint32_t> parent(nt);
  for (uint32_t t = 0; t < nt; ++t) parent[t] = t;
  auto find = [&](uint32_t t) {
    while (parent[t] != t) t = parent[t] = parent[parent[t]];
    return t;
  };
  for (uint32_t t = 0; t < nt; ++t)
    for (int i = 0; i < 3; ++i) {
      AdjacencyCode code = s.adjacency[3 * t + i];
      if (code == kNoNeighbour) continue;
      uint32_t n = code >> 3;
      int ne = static_cast<int>((code >> 1) & 3u);
      bool same_direction = code & 1u;
      // Same UVs on both sides of the edge: the two triangles are in one island.
      auto uv = [&](uint32_t tri, int corner) {
        return std::array<float, 2>{s.corner_uvs[6 * tri + 2 * corner], s.corner_uvs[6 * tri + 2 * corner + 1]};
      };
      int jn = (ne + (same_direction ? 1 : 2)) % 3, kn = (ne + (same_direction ? 2 : 1)) % 3;
      if (uv(t, (i + 1) % 3) == uv(n, jn) && uv(t, (i + 2) % 3) == uv(n, kn)) parent[find(t)] = find(n);
    }
  s.island.resize(nt);
  for (uint32_t t = 0; t < nt; ++t) s.island[t] = find(t);
}

double longest_edge(const Surface& s) {
  double max_edge = 0;
  for (uint32_t t = 0; t < s.triangle_count(); ++t)
    for (int c = 0; c < 3; ++c)
      max_edge = std::max(max_edge, norm(sub(vertex(s, s.triangles[3 * t + (c + 1) % 3]),
                                             vertex(s, s.triangles[3 * t + c]))));
  return max_edge;
}

// Sets triangle t's isometric frame, 3D axes and area, and returns its area; 0 (nothing
// set) where its 3D area is under area_eps.
double set_triangle_geometry(Surface& s, uint32_t t, double area_eps) {
  V3 p0 = vertex(s, s.triangles[3 * t]), p1 = vertex(s, s.triangles[3 * t + 1]),
     p2 = vertex(s, s.triangles[3 * t + 2]);
  V3 e1 = sub(p1, p0), e2 = sub(p2, p0);
  double area = 0.5 * norm(cross(e1, e2));
  double a = norm(e1);
  if (area <= area_eps || a == 0) return 0.0;
  double bx = dot(e2, e1) / a;
  double by = 2.0 * area / a;
  s.frames[t] = make_frame(a, bx, by);
  const double k = bx / a;
  const V3 ey{e2.x - k * e1.x, e2.y - k * e1.y, e2.z - k * e1.z};
  const double ny = norm(ey);
  const double iy = ny > 0 ? 1.0 / ny : 0.0;
  const double v[9] = {p0.x, p0.y, p0.z, e1.x / a, e1.y / a, e1.z / a, ey.x * iy, ey.y * iy, ey.z * iy};
  float* g = &s.frame3d[9 * static_cast<size_t>(t)];
  for (int i = 0; i < 9; ++i) g[i] = static_cast<float>(v[i]);
  s.areas[t] = static_cast<float>(area);
  return area;
}

// Neighbours across shared 3D edges (vertex indices, so UV seams are crossed), with
// walls around degenerate triangles; counts boundary and seam edges; refuses
// non-manifold edges.
void link_triangles(Surface& s) {
  const uint32_t nt = s.triangle_count();
  s.boundary_edges = s.seam_edges = 0;
  struct Side {
    uint32_t t;
    uint8_t edge;
  };
  std::unordered_map<uint64_t, std::vector<Side>> edges;
  edges.reserve(nt * 2);
  for (uint32_t t = 0; t < nt; ++t) {
    const uint32_t* v = &s.triangles[3 * t];
    // A triangle that repeats a vertex is a collapsed sliver: it borders nothing, and
    // its neighbours see a wall there.
    if (v[0] == v[1] || v[1] == v[2] || v[2] == v[0]) continue;
    for (uint8_t i = 0; i < 3; ++i) {
      uint32_t a = v[(i + 1) % 3], b = v[(i + 2) % 3];
      uint64_t key = (static_cast<uint64_t>(std::min(a, b)) << 32) | std::max(a, b);
      edges[key].push_back({t, i});
    }
  }
  s.adjacency.assign(3ull * nt, kNoNeighbour);
  uint32_t nonmanifold = 0;
  uint64_t example = 0;
  for (auto& [key, sides] : edges) {
    if (sides.size() > 2) {
      if (nonmanifold++ == 0) example = key;
      continue;
    }
    if (sides.size() == 1) {
      ++s.boundary_edges;
      continue;
    }
    Side x = sides[0], y = sides[1];
    if (x.t == y.t) {
      ++s.boundary_edges;
      continue;
    }
    uint32_t xa = s.triangles[3 * x.t + (x.edge + 1) % 3];
    uint32_t ya = s.triangles[3 * y.t + (y.edge + 1) % 3];
    // Consistently wound neighbours walk the shared edge in opposite directions; a
    // flipped neighbour walks it in the same direction.
    uint32_t same_direction = xa == ya ? 1u : 0u;
    auto uv_of = [&](Side side, int k) {
      const float* u = &s.corner_uvs[6 * side.t + 2 * ((side.edge + k) % 3)];
      return std::array<float, 2>{u[0], u[1]};
    };
    // A seam: the two sides of the edge sit at different UVs.
    auto x1 = uv_of(x, 1), x2 = uv_of(x, 2);
    auto y1 = uv_of(y, same_direction ? 1 : 2), y2 = uv_of(y, same_direction ? 2 : 1);
    if (x1 != y1 || x2 != y2) ++s.seam_edges;
    if (s.degenerate[x.t] || s.degenerate[y.t]) continue;  // walls around zero-area triangles
    s.adjacency[3 * x.t + x.edge] = (y.t << 3) | (static_cast<uint32_t>(y.edge) << 1) | same_direction;
    s.adjacency[3 * y.t + y.edge] = (x.t << 3) | (static_cast<uint32_t>(x.edge) << 1) | same_direction;
  }
  if (nonmanifold) {
    std::ostringstream m;
    m << "The mesh has " << nonmanifold << " non-manifold edge" << (nonmanifold > 1 ? "s" : "")
      << " (shared by more than two faces), e.g. between vertices " << (example >> 32) << " and "
      << (example & 0xffffffffu)
      << ": agents cannot tell which face to walk onto. Select them with Select > Select All by "
         "Trait > Non Manifold and fix them";
    fail(MOLDTEX_ERROR_INVALID_MESH, m.str());
  }
}

constexpr uint32_t kMaxTriangles = 1u << 28;  // leaves room for the adjacency packing

void validate(const moldtex_mesh_desc& d) {
  if (d.struct_size < sizeof(moldtex_mesh_desc))
    fail(MOLDTEX_ERROR_INVALID_ARGUMENT,
         "moldtex_mesh_desc.struct_size is too small: call moldtex_mesh_desc_init first");
  if ((d.triangle_count && !d.triangles) || (d.vertex_count && !d.positions) ||
      (d.uv_count && !d.uvs))
    fail(MOLDTEX_ERROR_INVALID_ARGUMENT, "A mesh array is NULL although its count is not zero");
  if (d.triangle_count == 0)
    fail(MOLDTEX_ERROR_INVALID_MESH, "The mesh has no faces: agents need triangles to walk on");
  if (d.vertex_count < 3)
    fail(MOLDTEX_ERROR_INVALID_MESH, "The mesh has fewer than three vertices");
  if (d.triangle_count > kMaxTriangles)
    fail(MOLDTEX_ERROR_TOO_LARGE, "The mesh has more than 268 million triangles");
  if ((d.uvs == nullptr) != (d.uv_count == 0))
    fail(MOLDTEX_ERROR_INVALID_ARGUMENT, "uvs and uv_count disagree: give both, or NULL and 0 for a mesh without UVs");
  if (d.uvs == nullptr && d.triangle_uvs != nullptr)
    fail(MOLDTEX_ERROR_INVALID_ARGUMENT, "triangle_uvs is given but there are no UVs");
  if (d.uvs && d.triangle_uvs == nullptr && d.uv_count != 3ull * d.triangle_count)
    fail(MOLDTEX_ERROR_INVALID_ARGUMENT,
         "Per-corner UVs need exactly 3 UVs per triangle (uv_count == 3 * triangle_count)");
  for (uint64_t i = 0; i < 3ull * d.vertex_count; ++i) {
    if (!std::isfinite(d.positions[i])) {
      std::ostringstream m;
      m << "Vertex " << i / 3 << " has a non-finite coordinate (NaN or infinity)";
      fail(MOLDTEX_ERROR_INVALID_MESH, m.str());
    }
    if (std::fabs(d.positions[i]) > kMaxCoordinate) {
      std::ostringstream m;
      m << "Vertex " << i / 3 << " has the coordinate " << d.positions[i] << ", beyond +-"
        << kMaxCoordinate << " units: float positions that far out cannot hold the mesh's shape. "
           "Move the mesh toward the origin or scale it down";
      fail(MOLDTEX_ERROR_INVALID_MESH, m.str());
    }
  }
  for (uint64_t i = 0; i < 2ull * d.uv_count; ++i) {
    if (!std::isfinite(d.uvs[i])) {
      std::ostringstream m;
      m << "UV " << i / 2 << " is not a finite number (NaN or infinity)";
      fail(MOLDTEX_ERROR_MISSING_UVS, m.str());
    }
    if (std::fabs(d.uvs[i]) > kMaxUvCoordinate) {
      std::ostringstream m;
      m << "UV " << i / 2 << " is (" << d.uvs[i - i % 2] << ", " << d.uvs[i - i % 2 + 1]
        << "), far outside the image: UV coordinates must lie within -" << kMaxUvCoordinate
        << " .. " << kMaxUvCoordinate
        << " (the pheromone texture covers 0 .. 1). Fix the UV map (UV > Reset, or Unwrap)";
      fail(MOLDTEX_ERROR_MISSING_UVS, m.str());
    }
  }
  for (uint64_t i = 0; i < 3ull * d.triangle_count; ++i) {
    if (d.triangles[i] >= d.vertex_count) {
      std::ostringstream m;
      m << "Triangle " << i / 3 << " refers to vertex " << d.triangles[i] << " but the mesh has only "
        << d.vertex_count << " vertices";
      fail(MOLDTEX_ERROR_INVALID_MESH, m.str());
    }
    if (d.triangle_uvs && d.triangle_uvs[i] >= d.uv_count) {
      std::ostringstream m;
      m << "Triangle " << i / 3 << " refers to UV " << d.triangle_uvs[i] << " but only " << d.uv_count
        << " UVs were given";
      fail(MOLDTEX_ERROR_INVALID_ARGUMENT, m.str());
    }
  }
}

}  // namespace

TriangleFrame make_frame(double a, double bx, double by) {
  TriangleFrame f{};
  f.a = static_cast<float>(a);
  f.bx = static_cast<float>(bx);
  f.by = static_cast<float>(by);
  f.inv_a = static_cast<float>(1.0 / a);
  f.inv_by = static_cast<float>(1.0 / by);
  const double q[3][2] = {{0, 0}, {a, 0}, {bx, by}};
  for (int i = 0; i < 3; ++i) {
    const double* from = q[(i + 1) % 3];
    const double* to = q[(i + 2) % 3];
    double dx = to[0] - from[0], dy = to[1] - from[1], n = std::sqrt(dx * dx + dy * dy);
    f.edge[i] = {static_cast<float>(dx / n), static_cast<float>(dy / n)};
    f.altitude[i] = static_cast<float>(a * by / n);
  }
  return f;
}

size_t Surface::bytes() const {
  return positions.capacity() * sizeof(float) + triangles.capacity() * sizeof(uint32_t) +
         corner_uvs.capacity() * sizeof(float) + frames.capacity() * sizeof(TriangleFrame) + frame3d.capacity() * sizeof(float) +
         adjacency.capacity() * sizeof(AdjacencyCode) + unfolded.capacity() * sizeof(float) + areas.capacity() * sizeof(float) +
         degenerate.capacity() + island.capacity() * sizeof(uint32_t);
}

std::array<double, 4> Surface::metric(uint32_t t) const {
  // J maps UV displacements to local-frame displacements: J = Q * T^-1 where the
  // columns of Q and T are the edges (corner1 - corner0, corner2 - corner0) in the local
  // frame and in UV. g = J^T J.
  const float* uv = &corner_uvs[6 * t];
  double t00 = uv[2] - uv[0], t10 = uv[3] - uv[1], t01 = uv[4] - uv[0], t11 = uv[5] - uv[1];
  double det = t00 * t11 - t01 * t10;
  if (degenerate[t] || det == 0.0) return {0, 0, 0, 0};
  double i00 = t11 / det, i01 = -t01 / det, i10 = -t10 / det, i11 = t00 / det;
  const TriangleFrame& f = frames[t];
  // Q = [[a, bx], [0, by]]
  double j00 = f.a * i00 + f.bx * i10, j01 = f.a * i01 + f.bx * i11;
  double j10 = f.by * i10, j11 = f.by * i11;
  return {j00 * j00 + j10 * j10, j00 * j01 + j10 * j11, j00 * j01 + j10 * j11, j01 * j01 + j11 * j11};
}

double Surface::area_per_uv_area(uint32_t t) const {
  auto g = metric(t);
  return std::sqrt(std::max(0.0, g[0] * g[3] - g[1] * g[2]));
}

void Surface::evaluate(uint32_t t, const float bary[3], float position[3], float uv[2]) const {
  if (position) {
    for (int k = 0; k < 3; ++k) {
      double p = 0;
      for (int c = 0; c < 3; ++c) p += bary[c] * positions[3 * triangles[3 * t + c] + k];
      position[k] = static_cast<float>(p);
    }
  }
  if (uv) {
    const float* u = &corner_uvs[6 * t];
    uv[0] = bary[0] * u[0] + bary[1] * u[2] + bary[2] * u[4];
    uv[1] = bary[0] * u[1] + bary[1] * u[3] + bary[2] * u[5];
  }
}

Surface build_surface(const moldtex_mesh_desc& d) {
  validate(d);
  Surface s;
  const uint32_t nt = d.triangle_count;
  s.positions.assign(d.positions, d.positions + 3ull * d.vertex_count);
  s.triangles.assign(d.triangles, d.triangles + 3ull * nt);
  s.generated_uvs = d.uvs == nullptr;
  if (s.generated_uvs) {
    s.corner_uvs = triangle_atlas_uvs(nt);
  } else {
    s.corner_uvs.resize(6ull * nt);
    for (uint64_t i = 0; i < 3ull * nt; ++i) {
      uint64_t src = d.triangle_uvs ? d.triangle_uvs[i] : i;
      s.corner_uvs[2 * i] = d.uvs[2 * src];
      s.corner_uvs[2 * i + 1] = d.uvs[2 * src + 1];
    }
  }

  // Frames, areas, degeneracy. Sizes are relative to the mesh so that tiny and huge
  // models behave the same.
  s.frames.resize(nt);
  s.frame3d.assign(9 * static_cast<size_t>(nt), 0.f);
  s.areas.resize(nt);
  s.degenerate.assign(nt, 0);
  const double max_edge = longest_edge(s);
  // Lengths are walked and areas summed in float: a mesh whose size float cannot carry
  // (areas underflow to 0 or overflow to infinity) is refused with its size.
  if (max_edge > 0 && (max_edge < kMinMeshSize || max_edge > kMaxMeshSize)) {
    std::ostringstream m;
    m << "The mesh is too " << (max_edge < kMinMeshSize ? "small" : "large") << " for Moldtex: its longest edge is "
      << max_edge << " units long, outside " << kMinMeshSize << " .. " << kMaxMeshSize
      << " units. Scale it (and apply the scale: Object > Apply > Scale) so that its edges "
         "are between those lengths";
    fail(MOLDTEX_ERROR_INVALID_MESH, m.str());
  }
  const double area_eps = 1e-12 * max_edge * max_edge;
  uint32_t flat_3d_count = 0;
  for (uint32_t t = 0; t < nt; ++t) {
    const float* uv = &s.corner_uvs[6 * t];
    double uv_area = 0.5 * std::fabs((uv[2] - uv[0]) * (uv[5] - uv[1]) - (uv[4] - uv[0]) * (uv[3] - uv[1]));
    const double area = set_triangle_geometry(s, t, area_eps);
    const bool flat_3d = area == 0.0;
    flat_3d_count += flat_3d;
    if (flat_3d || uv_area <= 1e-14) {
      s.degenerate[t] = 1;
      ++s.degenerate_count;
      s.frames[t] = make_frame(1.0, 0.0, 1.0);  // never walked on; keeps arithmetic finite
      std::fill_n(s.frame3d.begin() + 9 * static_cast<ptrdiff_t>(t), 9, 0.f);  // no 3D axes
      s.areas[t] = 0;
      continue;
    }
    s.area += area;
    s.uv_area += uv_area;
  }
  if (flat_3d_count == nt)
    fail(MOLDTEX_ERROR_INVALID_MESH, "Every triangle of the mesh has zero area");
  if (s.degenerate_count == nt || s.uv_area <= 1e-12)
    fail(MOLDTEX_ERROR_MISSING_UVS,
         "The UV map has zero area: unwrap the mesh (UV > Unwrap or Smart UV Project)");
  link_triangles(s);
  unfold_neighbours(s);
  label_islands(s);
  // FNV-1a over the inputs: checkpoints refuse to load onto a different mesh.
  uint64_t h = 1469598103934665603ull;
  auto hash = [&h](const void* data, size_t n) {
    const unsigned char* p = static_cast<const unsigned char*>(data);
    for (size_t i = 0; i < n; ++i) h = (h ^ p[i]) * 1099511628211ull;
  };
  hash(s.positions.data(), s.positions.size() * sizeof(float));
  hash(s.triangles.data(), s.triangles.size() * sizeof(uint32_t));
  hash(s.corner_uvs.data(), s.corner_uvs.size() * sizeof(float));
  s.fingerprint = h;
  return s;
}

std::shared_ptr<const Surface> walkable_in_3d(std::shared_ptr<const Surface> surface) {
  if (!surface || surface->degenerate_count == 0) return surface;
  const double max_edge = longest_edge(*surface);
  const double area_eps = 1e-12 * max_edge * max_edge;
  auto walkable = std::make_shared<Surface>(*surface);
  uint32_t opened = 0;
  for (uint32_t t = 0; t < walkable->triangle_count(); ++t) {
    if (!walkable->degenerate[t]) continue;
    const double area = set_triangle_geometry(*walkable, t, area_eps);
    if (area == 0.0) continue;  // flat in 3D as well: it stays a wall
    walkable->degenerate[t] = 0;
    --walkable->degenerate_count;
    walkable->area += area;
    ++opened;
  }
  if (opened == 0) return surface;
  link_triangles(*walkable);  // the islands stay those of the UV map
  unfold_neighbours(*walkable);
  return walkable;
}

}  // namespace moldtex
