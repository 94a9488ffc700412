#include "domain/intrinsic_domain.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <list>
#include <mutex>
#include <sstream>

#include "common/error.h"
#include "shared/intrinsic_locate.h"

namespace moldtex {

using intrinsic::kInvalid;
using intrinsic::SurfacePoint;
using intrinsic::Vec2d;

namespace {

// The spacing of the agents' sampling lattice (domain/intrinsic_lattice.h) along an input
// triangle's longest edge, in mean intrinsic edge lengths. Fig. 4's sphere of slivers
// (IntrinsicSimulation.SkinnyTrianglesGiveTheSamePattern) against the well-shaped one,
// gradient length: 1.0 -> 10.4 % apart, 0.7 -> 8.8 %, 0.5 -> 8.2 %; the Suzanne-sized
// benchmark ran as fast at 0.7 as at 1.0 and ~10 % slower at 0.5 (nodes per vertex at
// 0.7: 4.5 on the UV sphere 64 x 32 at 1024^2, 3.9 on a plane of right triangles).
constexpr double kLatticeSpacing = 0.7;

// Intrinsic vertices above this are refused before refining (each costs ~0.5 KiB with
// the operator, the correspondence and the tables).
constexpr double kMaxVertices = 16e6;
constexpr double kMaxPerTexel = 16;

std::array<double, 3> clean_bary(std::array<double, 3> b) {
  double s = 0;
  for (double& x : b) {
    x = std::isfinite(x) ? std::max(x, 0.0) : 0.0;
    s += x;
  }
  if (!(s > 0)) return {1.0 / 3, 1.0 / 3, 1.0 / 3};
  for (double& x : b) x /= s;
  return b;
}

Walker make_walker(const SurfacePoint& p, Vec2d heading) {
  Walker w{};
  w.triangle = p.face;
  const auto b = clean_bary(p.bary);
  for (int k = 0; k < 3; ++k) w.bary[k] = static_cast<float>(b[k]);
  const double n = intrinsic::norm(heading);
  w.heading = n > 0 ? Vec2{static_cast<float>(heading.x / n), static_cast<float>(heading.y / n)} : Vec2{1.f, 0.f};
  return w;
}

// Barycentrics of the UV point (u, v) in triangle t's UV corners (clamped onto it).
std::array<double, 3> uv_bary(const Surface& s, uint32_t t, double u, double v) {
  const float* c = s.corner_uvs.data() + 6ull * t;
  const double x0 = c[0], y0 = c[1], x1 = c[2], y1 = c[3], x2 = c[4], y2 = c[5];
  const double det = (x1 - x0) * (y2 - y0) - (x2 - x0) * (y1 - y0);
  if (!(std::fabs(det) > 0)) return {1.0 / 3, 1.0 / 3, 1.0 / 3};
  const double b1 = ((u - x0) * (y2 - y0) - (x2 - x0) * (v - y0)) / det;
  const double b2 = ((x1 - x0) * (v - y0) - (u - x0) * (y1 - y0)) / det;
  return clean_bary({1 - b1 - b2, b1, b2});
}

// Interleaves the low 21 bits of x, y, z (a 63-bit Morton code).
uint64_t spread(uint64_t x) {
  x &= 0x1fffff;
  x = (x | x << 32) & 0x1f00000000ffffull;
  x = (x | x << 16) & 0x1f0000ff0000ffull;
  x = (x | x << 8) & 0x100f00f00f00f00full;
  x = (x | x << 4) & 0x10c30c30c30c30c3ull;
  x = (x | x << 2) & 0x1249249249249249ull;
  return x;
}

// order[new] = old by ascending key (ties by old index), rank[old] = new.
void order_by(const std::vector<uint64_t>& key, std::vector<uint32_t>& order, std::vector<uint32_t>& rank) {
  order.resize(key.size());
  for (uint32_t i = 0; i < order.size(); ++i) order[i] = i;
  std::sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) { return key[a] != key[b] ? key[a] < key[b] : a < b; });
  rank.resize(key.size());
  for (uint32_t i = 0; i < order.size(); ++i) rank[order[i]] = i;
}

void number_along_a_curve(IntrinsicDomain& d) {
  const intrinsic::IntrinsicTriangulation& T = d.tri;
  const uint32_t nv = T.mesh.vertex_count(), nf = T.mesh.face_count();
  std::vector<std::array<double, 3>> x(nv, {0, 0, 0});
  std::array<double, 3> lo{HUGE_VAL, HUGE_VAL, HUGE_VAL}, hi{-HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
  for (uint32_t v = 0; v < nv; ++v) {
    if (T.corr.location[v].face == kInvalid) continue;
    x[v] = intrinsic::input_position(T, T.corr.location[v]);
    for (int k = 0; k < 3; ++k) lo[k] = std::min(lo[k], x[v][k]), hi[k] = std::max(hi[k], x[v][k]);
  }
  const double extent = std::max({hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2], 1e-30});
  auto code = [&](const std::array<double, 3>& p) {
    uint64_t c = 0;
    for (int k = 0; k < 3; ++k) {
      const double t = std::clamp((p[k] - lo[k]) / extent, 0.0, 1.0);
      c |= spread(static_cast<uint64_t>(t * 2097151.0)) << k;
    }
    return c;
  };
  std::vector<uint64_t> key(nv);
  for (uint32_t v = 0; v < nv; ++v) key[v] = code(x[v]);
  order_by(key, d.vertex_order, d.vertex_rank);
  key.assign(nf, 0);
  for (uint32_t f = 0; f < nf; ++f) {
    std::array<double, 3> c{0, 0, 0};
    for (uint32_t h : T.mesh.face_halfedges(f))
      for (int k = 0; k < 3; ++k) c[k] += x[T.mesh.tail(h)][k] / 3;
    key[f] = code(c);
  }
  order_by(key, d.face_order, d.face_rank);
}

void build_face_vertices(IntrinsicDomain& d) {
  const intrinsic::IntrinsicMesh& m = d.tri.mesh;
  const uint32_t nf = m.face_count();
  d.face_vertices.resize(3ull * nf);
  for (uint32_t f = 0; f < nf; ++f) {  // f: the new number
    const auto hs = m.face_halfedges(d.face_order[f]);
    for (int k = 0; k < 3; ++k) d.face_vertices[3ull * f + k] = d.vertex_rank[m.tail(hs[k])];
  }
}

void build_laplacian(IntrinsicDomain& d) {
  const intrinsic::IntrinsicMesh& m = d.tri.mesh;
  const uint32_t nv = m.vertex_count();
  std::vector<double> mass(nv, 0.0);
  for (uint32_t f = 0; f < m.face_count(); ++f) {
    const double third = m.face_area(f) / 3.0;
    for (uint32_t h : m.face_halfedges(f)) mass[d.vertex_rank[m.tail(h)]] += third;
  }
  // Edge conductances (cot alpha + cot beta) / 2, >= 0 on a Delaunay triangulation up
  // to round-off; a negative one (a flip the round-off kept) is clamped to 0 so the
  // operator stays an M-matrix (a maximum principle for the explicit steps).
  std::vector<CellEdge> edges;
  edges.reserve(m.edge_count());
  for (uint32_t e = 0; e < m.edge_count(); ++e) {
    const uint32_t h = 2 * e;
    const uint32_t a = d.vertex_rank[m.tail(h)], b = d.vertex_rank[m.head(h)];
    if (a == b) continue;  // a loop edge exchanges nothing
    double c = 0;
    for (uint32_t s : {h, h ^ 1u})
      if (m.he_face[s] != kInvalid) c += 0.5 * m.opposite_cotan(s);
    if (!(c > 0) || !std::isfinite(c)) continue;
    edges.push_back({std::min(a, b), std::max(a, b), static_cast<float>(c)});
  }
  // Parallel edges (a non-simplicial triangulation joins two vertices twice) add up.
  std::sort(edges.begin(), edges.end(), [](const CellEdge& x, const CellEdge& y) {
    return x.lo != y.lo ? x.lo < y.lo : x.hi < y.hi;
  });
  std::vector<CellEdge> merged;
  for (const CellEdge& e : edges) {
    if (!merged.empty() && merged.back().lo == e.lo && merged.back().hi == e.hi)
      merged.back().c += e.c;
    else
      merged.push_back(e);
  }
  std::vector<uint32_t> rows;
  std::vector<float> area(nv, 0.f);
  for (uint32_t v = 0; v < nv; ++v)
    if (mass[v] > 0) {
      rows.push_back(v);
      area[v] = static_cast<float>(mass[v]);
    }
  d.laplacian = laplacian_from_edges(std::move(rows), std::move(area), merged);
}

// Every island texel located on the intrinsic triangulation, through the locator (the
// point under the texel centre, on the triangle that covers it).
void build_texel_map(IntrinsicDomain& d, const Surface& s, const TextureDomain& td, ThreadPool& pool) {
  const size_t texels = td.texel_count();
  d.texel_face.assign(texels, IntrinsicDomain::kNone);
  d.texel_bary.assign(3 * texels, 0.f);
  const mtx_surface_tables tables = d.tables(mtx_surface_tables{});
  pool.parallel_for(texels, 4096, [&](size_t begin, size_t end) {
    for (size_t i = begin; i < end; ++i) {
      if (td.classes[i] != MOLDTEX_TEXEL_INSIDE || td.texel_triangle[i] < 0) continue;
      const uint32_t t = static_cast<uint32_t>(td.texel_triangle[i]);
      if (d.input_face[t] == kInvalid) continue;
      const double u = (i % td.width + 0.5) / td.width, v = (i / td.width + 0.5) / td.height;
      const auto b = uv_bary(s, t, u, v);
      const float bf[3] = {float(b[0]), float(b[1]), float(b[2])};
      mtx_u32 corners[3];
      d.texel_face[i] = mtx_locate_intrinsic(tables.locator_grid, tables.locator_cells, tables.locator_face,
                                             tables.locator_map, tables.locator_next, tables.locator_across,
                                             tables.face_vertices, t, bf, &d.texel_bary[3 * i], corners);
    }
  });
}

void build_vertex_texels(IntrinsicDomain& d, const Surface& s, const TextureDomain& td) {
  const intrinsic::IntrinsicTriangulation& T = d.tri;
  d.vertex_texel.assign(T.mesh.vertex_count(), 0);
  for (uint32_t v = 0; v < T.mesh.vertex_count(); ++v) {  // v: the new number
    const SurfacePoint& p = d.vertex_location(v);
    if (p.face == kInvalid) continue;
    const uint32_t t = T.input_triangle[p.face];
    const float* c = s.corner_uvs.data() + 6ull * t;
    const double u = p.bary[0] * c[0] + p.bary[1] * c[2] + p.bary[2] * c[4];
    const double w = p.bary[0] * c[1] + p.bary[1] * c[3] + p.bary[2] * c[5];
    d.vertex_texel[v] = td.texel_of_uv(static_cast<float>(u), static_cast<float>(w));
  }
}

std::shared_ptr<const IntrinsicDomain> build_intrinsic_domain(const Surface& s, const TextureDomain& td, double bound,
                                                              uint64_t max_insertions, ThreadPool& pool,
                                                              WorkProgress* progress) {
  const auto t0 = std::chrono::steady_clock::now();
  if (!(bound > 0) || !std::isfinite(bound))
    fail(MOLDTEX_ERROR_INVALID_ARGUMENT,
         "The circumradius bound of the intrinsic triangulation must be a positive length in mesh units");
  const double expected = 1.6 * s.area / (bound * bound);
  // A triangulation much finer than the texture shows nothing more and costs a lot of
  // time (the refinement inserts ~150 k vertices per second): at most kMaxPerTexel
  // vertices per island texel.
  size_t island = 0;
  for (size_t i = 0; i < td.texel_count(); ++i) island += td.classes[i] == MOLDTEX_TEXEL_INSIDE;
  const double texel_cap = kMaxPerTexel * std::max<double>(static_cast<double>(island), 256.0);
  if (expected > texel_cap && expected <= kMaxVertices) {
    std::ostringstream m;
    m.precision(3);
    m << "The intrinsic triangles of size " << bound << " (mesh units) would give about " << expected
      << " vertices for " << island << " texels of texture (at most " << kMaxPerTexel
      << " per texel): raise the Triangle Size or the resolution";
    fail(MOLDTEX_ERROR_TOO_LARGE, m.str());
  }
  if (expected > kMaxVertices) {
    std::ostringstream m;
    m.precision(3);
    m << "The intrinsic triangulation at a circumradius bound of " << bound << " mesh units would have about "
      << expected << " vertices, more than the limit of " << kMaxVertices
      << ": raise the bound or lower the texture resolution";
    fail(MOLDTEX_ERROR_TOO_LARGE, m.str());
  }
  auto d = std::make_shared<IntrinsicDomain>();
  d->bound = bound;
  auto stage = [&](uint32_t next) {
    if (!progress) return;
    progress->check_cancel();
    progress->enter(next);
  };
  stage(MOLDTEX_BUILD_REFINING);
  d->tri = intrinsic::build_intrinsic_triangulation(s);
  intrinsic::RefineOptions options;
  options.max_circumradius = bound;
  options.max_insertions = max_insertions;
  options.area = s.area;  // the cap from the mesh's true area, as sim.cpp's memory check
  options.progress = progress;
  options.expected_vertices = kExpectedVerticesPerBound2 * s.area / (bound * bound) + d->tri.mesh.vertex_count();
  d->report = intrinsic::refine(d->tri, options);
  if (d->report.reason != intrinsic::StopReason::Converged)
    fail(MOLDTEX_ERROR_TOO_LARGE, "The intrinsic triangulation could not be refined to the bound " +
                                      std::to_string(bound) + ": " + d->report.message +
                                      " Raise the bound (a coarser triangulation) or use the Texture domain.");
  d->input_face.assign(s.triangle_count(), kInvalid);
  for (uint32_t f = 0; f < d->tri.input_triangle.size(); ++f) d->input_face[d->tri.input_triangle[f]] = f;
  stage(MOLDTEX_BUILD_OPERATORS);
  if (progress) progress->count.store(d->tri.mesh.vertex_count(), std::memory_order_relaxed);
  // Within the stage, the share of its time each part took on the 100 k-triangle torus
  // (numbering 14%, corners 3%, Laplacian 23%, locator 60%).
  auto part_done = [&](double fraction) {
    if (progress) progress->stage_fraction.store(fraction, std::memory_order_relaxed);
  };
  number_along_a_curve(*d);
  part_done(0.14);
  build_face_vertices(*d);
  part_done(0.17);
  build_laplacian(*d);
  part_done(0.40);
  const double face_area = d->tri.mesh.total_area() / std::max<uint32_t>(d->tri.mesh.face_count(), 1);
  d->locator = build_intrinsic_locator(s, d->tri, d->input_face, d->face_rank, d->face_order, d->face_vertices,
                                       face_area, pool);
  // Deposit pieces of at most one bound along the walk (per surface triangle, where the
  // continuous step looks them up): 0.7-0.8 of a mean intrinsic edge, so each piece's
  // hats still overlap the next's, as the texture domain's pieces of one texel do. Half
  // a bound (until 2026-12-05) put 5 pieces in a default step on Suzanne at 1024^2 instead
  // of 3, for the same pattern measures (test_intrinsic_domain.cpp), 7-9% of the step.
  d->cells_per_unit.assign(2ull * s.triangle_count(), static_cast<float>(1.0 / bound));
  // Lattice nodes kLatticeSpacing mean intrinsic edges apart (the mean edge: that of an
  // equilateral triangle of the mean face area).
  d->lattice = build_intrinsic_lattice(s, d->tri, d->input_face, d->face_rank, d->face_vertices,
                                       kLatticeSpacing * std::sqrt(4.0 * face_area / std::sqrt(3.0)), pool);
  part_done(1.0);
  stage(MOLDTEX_BUILD_TEXEL_MAP);
  build_texel_map(*d, s, td, pool);
  build_vertex_texels(*d, s, td);
  d->build_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  stage(MOLDTEX_BUILD_DONE);
  return d;
}

}  // namespace

mtx_surface_tables IntrinsicDomain::tables(mtx_surface_tables t) const {
  t.texels_per_unit = cells_per_unit.data();
  t.face_vertices = face_vertices.data();
  t.locator_grid = locator.grid.data();
  t.locator_cells = locator.cells.data();
  t.locator_face = locator.face.data();
  t.locator_map = locator.map.data();
  t.locator_next = locator.next.data();
  t.locator_across = locator.across.data();
  t.vertex_cells = 1u;
  return t;
}

mtx_surface_tables IntrinsicDomain::agent_tables(mtx_surface_tables surface, const float* lattice_field) const {
  mtx_surface_tables t = tables(surface);
  t.lattice = lattice.grid.data();
  t.lattice_field = lattice_field;
  return t;
}

void IntrinsicDomain::gather(const float* values, float* texels, ThreadPool& pool) const {
  pool.parallel_for(texel_face.size(), 4096, [&](size_t begin, size_t end) {
    for (size_t i = begin; i < end; ++i) {
      const uint32_t f = texel_face[i];
      if (f == kNone) continue;
      const uint32_t* v = face_vertices.data() + 3ull * f;
      const float* b = texel_bary.data() + 3 * i;
      texels[i] = b[0] * values[v[0]] + b[1] * values[v[1]] + b[2] * values[v[2]];
    }
  });
}

std::vector<float> IntrinsicDomain::sample_texels(const float* texels) const {
  std::vector<float> out(vertex_texel.size());
  for (size_t v = 0; v < out.size(); ++v) out[v] = texels[vertex_texel[v]];
  return out;
}

void IntrinsicDomain::show(const float* values, float* texels, uint32_t planes, const TextureDomain& texture,
                           ThreadPool& pool) const {
  const size_t n = texture.texel_count(), nv = vertex_count();
  std::fill(texels, texels + n * planes, 0.f);
  for (uint32_t k = 0; k < planes; ++k) {
    gather(values + k * nv, texels + k * n, pool);
    fill_gutter(texture, texels + k * n, pool);
  }
}

std::vector<float> IntrinsicDomain::values_from_state(const SimState& state, uint32_t planes,
                                                      const TextureDomain& texture, ThreadPool& pool) const {
  const size_t texels = texture.texel_count(), nv = vertex_count();
  if (state.pheromone.size() != texels * planes)
    fail(MOLDTEX_ERROR_INTERNAL, "The state's planes do not match the texture");
  std::vector<float> next(nv * planes, 0.f);
  if (state.cells.size() == next.size()) {
    // Untouched, the planes are exactly what the values show, and the state comes back
    // bit for bit; a texel changed since moves the vertex under it by as much, but no
    // further than the texel's new value: a vertex below what its texel showed (its
    // neighbours higher) and then dabbed down would otherwise go negative. Between its
    // old value and the painted one, it stays in any range both lie in.
    next = state.cells;
    std::vector<float> shown(texels * planes);
    show(state.cells.data(), shown.data(), planes, texture, pool);
    for (uint32_t k = 0; k < planes; ++k)
      for (size_t v = 0; v < nv; ++v) {
        const size_t i = k * texels + vertex_texel[v];
        const float painted = state.pheromone[i];
        if (painted == shown[i]) continue;
        float& value = next[k * nv + v];
        const float moved = value + (painted - shown[i]);
        value = std::clamp(moved, std::min(value, painted), std::max(value, painted));
      }
  } else {
    for (uint32_t k = 0; k < planes; ++k)
      for (size_t v = 0; v < nv; ++v) next[k * nv + v] = state.pheromone[k * texels + vertex_texel[v]];
  }
  return next;
}

ParameterMaps IntrinsicDomain::vertex_maps(const ParameterMaps& maps, size_t texels) const {
  const size_t nv = vertex_count();
  ParameterMaps v;
  for (uint32_t k = 0; k < MOLDTEX_MAP_COUNT; ++k)
    if (!maps.given[k].empty()) v.given[k] = sample_texels(maps.given[k].data());
  const size_t planes = texels ? maps.agent_planes.size() / texels : 0;
  v.agent_planes.resize(planes * nv);
  for (size_t p = 0; p < planes; ++p) {
    const std::vector<float> s = sample_texels(maps.agent_planes.data() + p * texels);
    std::copy(s.begin(), s.end(), v.agent_planes.begin() + p * nv);
  }
  std::copy(std::begin(maps.plane_of), std::end(maps.plane_of), std::begin(v.plane_of));
  v.deposit_max = maps.deposit_max;
  v.largest = maps.largest;
  v.version = maps.version;
  v.spawn_max = maps.spawn_max;
  v.spawn_alias = maps.spawn_alias;
  return v;
}

const ParameterMaps& VertexMaps::of(const IntrinsicDomain& domain, const ParameterMaps& maps, size_t texels) {
  if (source_ != &maps || version_ != maps.version) {
    maps_ = domain.vertex_maps(maps, texels);
    source_ = &maps;
    version_ = maps.version;
  }
  return maps_;
}

Walker IntrinsicDomain::to_intrinsic(const Walker& w) const {
  const uint32_t face = w.triangle < input_face.size() ? input_face[w.triangle] : kInvalid;
  if (face == kInvalid) {  // a dropped triangle (no area, never walked on): face 0
    SurfacePoint p;
    p.face = 0;
    p.bary = {1.0 / 3, 1.0 / 3, 1.0 / 3};
    return make_walker(p, {1, 0});
  }
  const LocatedPoint at = locate_from_corner(tri, face, {w.bary[0], w.bary[1], w.bary[2]});
  SurfacePoint p = at.point;
  p.face = face_rank[p.face];
  const double c = std::cos(at.turn), s = std::sin(at.turn);
  return make_walker(p, {c * w.heading.x - s * w.heading.y, s * w.heading.x + c * w.heading.y});
}

Walker IntrinsicDomain::to_input(const Walker& w) const {
  const LocatedPoint at = locate_on_input(tri, face_order[w.triangle], {w.bary[0], w.bary[1], w.bary[2]});
  SurfacePoint p = at.point;
  p.face = tri.input_triangle[p.face];
  const double c = std::cos(at.turn), s = std::sin(at.turn);
  return make_walker(p, {c * w.heading.x - s * w.heading.y, s * w.heading.x + c * w.heading.y});
}

size_t IntrinsicDomain::bytes() const {
  const intrinsic::IntrinsicMesh& m = tri.mesh;
  const size_t mesh = m.halfedge_count() * (4 * 3 + 8) + m.edge_count() * 8 + m.face_count() * 4 +
                      m.vertex_count() * (4 + 8 + 1);
  return 2 * mesh + tri.corr.location.size() * 32 + (face_vertices.size() + cells_per_unit.size()) * 4 +
         locator.bytes() + lattice.bytes() + laplacian.bytes() + texel_face.size() * 16 + vertex_texel.size() * 4 +
         (face_order.size() + vertex_order.size()) * 8;
}

double default_intrinsic_bound(const TextureDomain& d) {
  double area = 0;
  size_t cells = 0;
  const double per_texel = 1.0 / (static_cast<double>(d.width) * d.height);
  for (size_t i = 0; i < d.texel_count(); ++i)
    if (d.classes[i] == MOLDTEX_TEXEL_INSIDE && d.texel_triangle[i] >= 0) {
      area += d.triangle_area_scale[d.texel_triangle[i]] * per_texel;
      ++cells;
    }
  return cells > 0 && area > 0 ? std::sqrt(area / static_cast<double>(cells)) : 0.0;
}

std::shared_ptr<const IntrinsicDomain> IntrinsicDomainCache::find(uint64_t fingerprint, uint32_t width,
                                                                  uint32_t height, double bound,
                                                                  uint64_t max_insertions) {
  std::lock_guard<std::mutex> lock(mutex_);
  for (auto it = entries_.begin(); it != entries_.end(); ++it)
    if (it->fingerprint == fingerprint && it->width == width && it->height == height && it->bound == bound &&
        it->max_insertions == max_insertions) {
      entries_.splice(entries_.begin(), entries_, it);
      return entries_.front().domain;
    }
  return nullptr;
}

void IntrinsicDomainCache::put(uint64_t fingerprint, uint32_t width, uint32_t height, double bound,
                               uint64_t max_insertions, std::shared_ptr<const IntrinsicDomain> domain) {
  std::lock_guard<std::mutex> lock(mutex_);
  entries_.push_front({fingerprint, width, height, bound, max_insertions, std::move(domain)});
  while (entries_.size() > kEntries) entries_.pop_back();
}

void IntrinsicDomainCache::clear() {
  std::list<Entry> dropped;  // released outside the lock
  std::lock_guard<std::mutex> lock(mutex_);
  dropped.swap(entries_);
}

size_t IntrinsicDomainCache::size() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return entries_.size();
}

const std::shared_ptr<IntrinsicDomainCache>& default_intrinsic_cache() {
  static const std::shared_ptr<IntrinsicDomainCache> cache = std::make_shared<IntrinsicDomainCache>();
  return cache;
}

std::shared_ptr<const IntrinsicDomain> intrinsic_domain_for(const Surface& surface, const TextureDomain& domain,
                                                            double bound, uint64_t max_insertions,
                                                            ThreadPool& pool, IntrinsicDomainCache& cache,
                                                            bool* from_cache, WorkProgress* progress) {
  if (from_cache) *from_cache = false;
  if (auto found = cache.find(surface.fingerprint, domain.width, domain.height, bound, max_insertions)) {
    if (from_cache) *from_cache = true;
    return found;
  }
  auto built = build_intrinsic_domain(surface, domain, bound, max_insertions, pool, progress);
  cache.put(surface.fingerprint, domain.width, domain.height, bound, max_insertions, built);
  return built;
}

}  // namespace moldtex
