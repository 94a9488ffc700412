#include "domain/intrinsic_locator.h"

#include <algorithm>
#include <cmath>

#include "shared/constants.h"
#include "shared/intrinsic_locate.h"

namespace moldtex {

using intrinsic::kInvalid;
using intrinsic::SurfacePoint;
using intrinsic::Vec2d;

namespace {

constexpr uint32_t kMaxGrid = 2048;  // cells per side of one input triangle
// Intrinsic faces per cell (by area): larger cells hold fewer candidates per face (a face
// is listed in every cell it overlaps) but leave more to the walk.
constexpr double kFacesPerCell = 2.0;

double angle_of(Vec2d d) { return std::atan2(d.y, d.x); }

Vec2d rotate(Vec2d d, double a) {
  const double c = std::cos(a), s = std::sin(a);
  return {c * d.x - s * d.y, s * d.x + c * d.y};
}

Vec2d point_in(const std::array<Vec2d, 3>& P, const std::array<double, 3>& b) {
  return b[0] * P[0] + b[1] * P[1] + b[2] * P[2];
}

// The 3 x 3 map from face f's barycentrics to those of its neighbour across halfedge h
// (of f): the plane of f unfolded onto g's about the shared edge, so points beyond the
// edge land inside g. Column j: f's corner j in g's weights.
std::array<double, 9> across_edge(const intrinsic::IntrinsicMesh& m, uint32_t f, uint32_t h) {
  const uint32_t tw = intrinsic::IntrinsicMesh::twin(h), g = m.he_face[tw];
  const auto F = m.layout(f), G = m.layout(g);
  const int i = m.corner_index(h), k = m.corner_index(tw);
  // h runs F[i] -> F[i + 1]; tw runs G[k] -> G[k + 1], the same edge the other way.
  const Vec2d A = F[i], B = F[(i + 1) % 3], A2 = G[(k + 1) % 3], B2 = G[k];
  const Vec2d u = (1.0 / std::max(intrinsic::norm(B - A), 1e-300)) * (B - A);
  const Vec2d u2 = (1.0 / std::max(intrinsic::norm(B2 - A2), 1e-300)) * (B2 - A2);
  std::array<double, 9> T{};
  for (int j = 0; j < 3; ++j) {
    const Vec2d x = F[j] - A;
    const double along = intrinsic::dot(x, u), across = intrinsic::cross(u, x);
    const Vec2d y = A2 + along * u2 + across * Vec2d{-u2.y, u2.x};
    const auto c = intrinsic::barycentric(G, y);
    for (int r = 0; r < 3; ++r) T[3 * r + j] = c[r];
  }
  return T;
}

// Samples are taken a hair inside the triangle: a trace that ends exactly on a corner
// (an input vertex, a cone of the surface) may end in any face around it, with a frame
// that holds only on the far side of the cone, so a map made from it would be wrong by
// the cone's angle defect.
std::array<double, 3> inward(const std::array<double, 3>& b) {
  constexpr double kInset = 1e-3;
  return {kInset / 3 + (1 - kInset) * b[0], kInset / 3 + (1 - kInset) * b[1], kInset / 3 + (1 - kInset) * b[2]};
}

// A convex polygon in an input triangle's (b1, b2) plane: a cell (at most 4 corners) cut
// by at most 4 lines, so at most 8 corners.
struct Polygon {
  std::array<std::array<double, 2>, 8> v;
  size_t n = 0;
  void push_back(const std::array<double, 2>& p) {
    if (n < v.size()) v[n++] = p;
  }
};

double weight_at(const std::array<double, 9>& M, int r, const std::array<double, 2>& p) {
  return M[3 * r] * (1 - p[0] - p[1]) + M[3 * r + 1] * p[0] + M[3 * r + 2] * p[1];
}

// The polygon clipped to where weight row r of the map c = M b (b0 = 1 - b1 - b2) is >= 0.
Polygon clip(const Polygon& in, const std::array<double, 9>& M, int r) {
  Polygon out;
  for (size_t i = 0; i < in.n; ++i) {
    const auto& a = in.v[i];
    const auto& b = in.v[(i + 1) % in.n];
    const double wa = weight_at(M, r, a), wb = weight_at(M, r, b);
    if (wa >= 0) out.push_back(a);
    if ((wa >= 0) != (wb >= 0)) {
      const double t = wa / (wa - wb);
      out.push_back({a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])});
    }
  }
  return out;
}

double polygon_area(const Polygon& p) {
  double a = 0;
  for (size_t i = 0; i < p.n; ++i) {
    const auto& u = p.v[i];
    const auto& w = p.v[(i + 1) % p.n];
    a += u[0] * w[1] - u[1] * w[0];
  }
  return 0.5 * std::fabs(a);
}

// Whether the polygon (already inside the face) runs along the face's edge k (where its
// weight k is 0) for a positive length: the neighbour across that edge then overlaps
// the polygon's cell too.
bool runs_along_edge(const Polygon& p, const std::array<double, 9>& M, int k) {
  constexpr double kOnLine = 1e-12;
  const std::array<double, 2>* first = nullptr;
  for (size_t i = 0; i < p.n; ++i) {
    const auto& v = p.v[i];
    if (std::fabs(weight_at(M, k, v)) > kOnLine) continue;
    if (first == nullptr)
      first = &v;
    else if (std::fabs(v[0] - (*first)[0]) + std::fabs(v[1] - (*first)[1]) > kOnLine)
      return true;
  }
  return false;
}

}  // namespace

// The trace from the nearest corner of `from_face` (on `from`) to the point q of that
// face, replayed on the other mesh by `trace` (vertex, tangent angle, distance). A point
// within round-off of its corner is moved a hair toward the face's centre, so the trace
// has a direction (and the turn is defined).
template <class Trace>
LocatedPoint locate_by_corner(const intrinsic::IntrinsicMesh& from, uint32_t from_face, std::array<double, 3> bary,
                              double scale, Trace trace) {
  const auto P = from.layout(from_face);
  Vec2d q = point_in(P, bary);
  int k = 0;
  for (int i = 1; i < 3; ++i)
    if (intrinsic::norm(P[i] - q) < intrinsic::norm(P[k] - q)) k = i;
  Vec2d d = q - P[k];
  if (!(intrinsic::norm(d) > 1e-9 * scale)) {
    const Vec2d centre = (1.0 / 3.0) * (P[0] + P[1] + P[2]);
    d = 1e-6 * (centre - P[k]);
  }
  const uint32_t v = from.tail(from.face_halfedges(from_face)[k]);
  const intrinsic::TraceResult r = trace(v, intrinsic::tangent_angle(from, from_face, k, d), intrinsic::norm(d));
  return {r.point, angle_of(r.direction) - angle_of(d)};
}

LocatedPoint locate_from_corner(const intrinsic::IntrinsicTriangulation& T, uint32_t face,
                                const std::array<double, 3>& bary) {
  return locate_by_corner(T.input, face, bary, T.mean_edge, [&](uint32_t v, double angle, double dist) {
    return intrinsic::trace_from_vertex(T.mesh, v, angle, dist);
  });
}

LocatedPoint locate_on_input(const intrinsic::IntrinsicTriangulation& T, uint32_t face,
                             const std::array<double, 3>& bary) {
  return locate_by_corner(T.mesh, face, bary, T.mean_edge, [&](uint32_t v, double angle, double dist) {
    return intrinsic::trace_input_from_vertex(T, v, angle, dist);
  });
}

std::vector<LocatedPoint> locate_chain(const intrinsic::IntrinsicTriangulation& T, uint32_t face,
                                       const std::vector<std::array<double, 3>>& bary) {
  std::vector<LocatedPoint> out(bary.size());
  const auto P = T.input.layout(face);
  Vec2d at_q{};
  for (size_t k = 0; k < bary.size(); ++k) {
    const Vec2d q = point_in(P, bary[k]);
    const Vec2d step = q - at_q;
    const double dist = intrinsic::norm(step);
    bool ok = false;
    if (k > 0 && dist < 1e-12 * T.mean_edge) {
      out[k] = out[k - 1];
      ok = true;
    } else if (k > 0) {
      const intrinsic::TraceResult r =
          intrinsic::trace_from_point(T.mesh, out[k - 1].point, rotate(step, out[k - 1].turn), dist);
      if (r.complete && r.boundary_he == kInvalid) {
        out[k] = {r.point, angle_of(r.direction) - angle_of(step)};
        ok = true;
      }
    }
    if (!ok) out[k] = locate_from_corner(T, face, bary[k]);  // the first, or a trace that met the boundary
    at_q = q;
  }
  return out;
}

IntrinsicLocator build_intrinsic_locator(const Surface& surface, const intrinsic::IntrinsicTriangulation& T,
                                         const std::vector<uint32_t>& input_face,
                                         const std::vector<uint32_t>& face_rank,
                                         const std::vector<uint32_t>& face_order,
                                         const std::vector<uint32_t>& face_vertices, double face_area,
                                         ThreadPool& pool) {
  const uint32_t nt = surface.triangle_count();
  IntrinsicLocator L;
  // The walk's tables, in the domain's face numbering.
  const intrinsic::IntrinsicMesh& mesh = T.mesh;
  const uint32_t nf = mesh.face_count();
  L.next.assign(3ull * nf, MTX_NO_NEIGHBOUR);
  L.across.assign(9ull * nf, 0.f);
  pool.parallel_for(nf, 1024, [&](size_t begin, size_t end) {
    for (size_t fn = begin; fn < end; ++fn) {
      const uint32_t f = face_order[fn];
      const auto hs = mesh.face_halfedges(f);
      for (int k = 0; k < 3; ++k) {
        const uint32_t h = hs[(k + 1) % 3], tw = intrinsic::IntrinsicMesh::twin(h), g = mesh.he_face[tw];
        if (g == kInvalid) continue;
        const int m = mesh.corner_index(tw);
        const std::array<double, 9> A = across_edge(mesh, g, tw);  // g's weights -> f's
        for (int r = 0; r < 3; ++r) L.across[9 * fn + 3 * k + r] = static_cast<float>(A[3 * r + (m + 2) % 3]);
        L.next[3 * fn + k] = (face_rank[g] << 2) | static_cast<uint32_t>(m);
      }
    }
  });
  L.grid.assign(2ull * nt, 0);
  // Grid sizes first (cell numbering is a prefix sum): about one cell per intrinsic face
  // the triangle holds.
  uint64_t total = 0;
  for (uint32_t t = 0; t < nt; ++t) {
    const uint32_t f = input_face[t];
    if (f == kInvalid || surface.degenerate[t]) continue;
    const double a = T.input.face_area(f);
    const double g = std::ceil(std::sqrt(2.0 * a / (kFacesPerCell * std::max(face_area, 1e-300))));
    const uint32_t G = static_cast<uint32_t>(std::clamp(g, 1.0, double(kMaxGrid)));
    L.grid[2ull * t] = static_cast<uint32_t>(total);
    L.grid[2ull * t + 1] = G;
    total += uint64_t(G) * (G + 1) / 2;
  }
  // Per triangle: its candidates (face, map) per cell, made in parallel, joined in order.
  struct Candidates {
    std::vector<uint32_t> count;  // per cell
    std::vector<uint32_t> face;
    std::vector<float> map;
  };
  std::vector<Candidates> per(nt);
  pool.parallel_for(nt, 16, [&](size_t begin, size_t end) {
    for (size_t t = begin; t < end; ++t) {
      const uint32_t G = L.grid[2 * t + 1], f = input_face[t];
      if (G == 0) continue;
      Candidates& out = per[t];
      const auto P = T.input.layout(f);
      // Samples: the lattice points (a, b) / G with a + b <= G, row by row (each row in
      // turn forwards and backwards, so the chain's steps stay short), then the cell
      // centres.
      std::vector<std::array<double, 3>> bary;
      std::vector<uint32_t> lattice_index((G + 1) * (G + 1), 0);
      for (uint32_t a = 0; a <= G; ++a)
        for (uint32_t s = 0; s <= G - a; ++s) {
          const uint32_t b = a % 2 == 0 ? s : G - a - s;
          lattice_index[a * (G + 1) + b] = static_cast<uint32_t>(bary.size());
          const double b1 = double(a) / G, b2 = double(b) / G;
          bary.push_back(inward({std::max(0.0, 1 - b1 - b2), b1, b2}));
        }
      const size_t centres = bary.size();
      for (uint32_t i = 0; i < G; ++i)
        for (uint32_t j = 0; i + j < G; ++j) {
          double b1 = (i + 0.5) / G, b2 = (j + 0.5) / G;
          if (b1 + b2 > 1) {  // the last cell of a row: its centre onto the hypotenuse
            const double s = 1 / (b1 + b2);
            b1 *= s, b2 *= s;
          }
          bary.push_back(inward({std::max(0.0, 1 - b1 - b2), b1, b2}));
        }
      const std::vector<LocatedPoint> at = locate_chain(T, f, bary);
      // The map of the face that sample k landed in: c = M b.
      auto map_of = [&](size_t k) {
        std::array<double, 9> M{};
        const LocatedPoint& p = at[k];
        const auto F = T.mesh.layout(p.point.face);
        const Vec2d qs = point_in(P, bary[k]), Qs = point_in(F, p.point.bary);
        for (int corner = 0; corner < 3; ++corner) {
          const Vec2d Q = rotate(P[corner] - qs, p.turn) + Qs;
          const auto c = intrinsic::barycentric(F, Q);
          for (int r = 0; r < 3; ++r) M[3 * r + corner] = c[r];
        }
        return M;
      };
      // Candidates: every face that overlaps the cell, the largest overlap first (the
      // lookup's first try then usually holds the point). First the faces the cell's
      // samples landed in, then, face to face, each neighbour across an edge that runs
      // through the cell, its map the face's unfolded across that edge (with the walk's
      // tables: the corner d beyond edge k has weights e in the face, so a point with
      // weights c there is c[a] - t e[a] of a, c[b] - t e[b] of b and t = c[k] / e[k] of
      // d in the neighbour). The lookup's walk is then left the points within round-off
      // of an edge, where it was 40% of all lookups with the samples' faces alone.
      struct Candidate {
        uint32_t face;  // the triangulation's number
        std::array<double, 9> M;
        double area;
      };
      constexpr size_t kMaxCandidates = 32;  // a cell of needles: the walk does the rest
      std::vector<Candidate> found;
      out.count.reserve(size_t(G) * (G + 1) / 2);
      const std::array<double, 9> identity{1, 0, 0, 0, 1, 0, 0, 0, 1};
      for (uint32_t i = 0; i < G; ++i)
        for (uint32_t j = 0; i + j < G; ++j) {
          const size_t cell_centre = centres + (size_t(i) * G - size_t(i) * (i - 1) / 2 + j);
          size_t samples[5] = {cell_centre, lattice_index[i * (G + 1) + j], lattice_index[(i + 1) * (G + 1) + j],
                               lattice_index[i * (G + 1) + j + 1], 0};
          int n = 4;
          if (i + j + 2 <= G) samples[n++] = lattice_index[(i + 1) * (G + 1) + j + 1];
          found.clear();
          auto listed = [&](uint32_t face) {
            return std::any_of(found.begin(), found.end(), [&](const Candidate& c) { return c.face == face; });
          };
          for (int s = 0; s < n; ++s) {
            const uint32_t face = at[samples[s]].point.face;
            if (!listed(face)) found.push_back({face, map_of(samples[s]), 0.0});
          }
          // The cell: [i, i + 1] x [j, j + 1] / G in (b1, b2), cut by b1 + b2 <= 1.
          Polygon cell;
          cell.push_back({double(i) / G, double(j) / G});
          cell.push_back({double(i + 1) / G, double(j) / G});
          cell.push_back({double(i + 1) / G, double(j + 1) / G});
          cell.push_back({double(i) / G, double(j + 1) / G});
          cell = clip(cell, identity, 0);
          for (size_t q = 0; q < found.size(); ++q) {
            Polygon part = cell;
            for (int r = 0; r < 3 && part.n > 0; ++r) part = clip(part, found[q].M, r);
            found[q].area = polygon_area(part);
            const uint32_t rank = face_rank[found[q].face];
            for (int k = 0; k < 3 && part.n >= 2 && found.size() < kMaxCandidates; ++k) {
              if (!runs_along_edge(part, found[q].M, k)) continue;
              const uint32_t code = L.next[3ull * rank + k];
              const float* e = &L.across[9ull * rank + 3 * k];
              if (code == MTX_NO_NEIGHBOUR || !(e[k] < 0.f)) continue;
              const uint32_t g = face_order[code >> 2];
              if (listed(g)) continue;
              const int m = static_cast<int>(code & 3u), a = (k + 1) % 3, b = (k + 2) % 3;
              std::array<double, 9> M{};
              for (int col = 0; col < 3; ++col) {
                double c[3];
                for (int r = 0; r < 3; ++r) c[r] = found[q].M[3 * r + col];
                const double t = c[k] / e[k];
                M[3 * m + col] = c[b] - t * e[b];
                M[3 * ((m + 1) % 3) + col] = c[a] - t * e[a];
                M[3 * ((m + 2) % 3) + col] = t;
              }
              found.push_back({g, M, 0.0});
            }
          }
          std::stable_sort(found.begin(), found.end(),
                           [](const Candidate& a, const Candidate& b) { return a.area > b.area; });
          for (const Candidate& c : found) {
            const uint32_t rank = face_rank[c.face];
            out.face.push_back(rank);
            for (int r = 0; r < 3; ++r) out.face.push_back(face_vertices[3ull * rank + r]);
            for (int r = 0; r < 6; ++r) out.map.push_back(static_cast<float>(c.M[r]));
          }
          out.count.push_back(static_cast<uint32_t>(found.size()));
        }
    }
  });
  // Each cell's first candidate (the largest overlap, which holds most points) is record
  // `cell` itself, so a lookup reads it straight from the cell's number; the others follow
  // all the first ones, cells[cell] to cells[cell + 1]. A cell without candidates (none is
  // built) gets a first record that gives every point weights 1/3 in face 0.
  size_t candidates = 0;
  for (const Candidates& c : per) candidates += c.face.size() / MTX_LOCATE_FACE_STRIDE;
  const size_t cell_count = total;
  candidates = std::max(candidates, cell_count);
  L.face.assign(MTX_LOCATE_FACE_STRIDE * cell_count, 0);
  L.map.assign(MTX_LOCATE_MAP_STRIDE * cell_count, 0.f);
  L.face.reserve(MTX_LOCATE_FACE_STRIDE * candidates);
  L.map.reserve(MTX_LOCATE_MAP_STRIDE * candidates);
  L.cells.reserve(cell_count + 1);
  size_t cell = 0;
  for (uint32_t t = 0; t < nt; ++t) {  // cells in the grid's order: triangle by triangle
    const Candidates& c = per[t];
    size_t k = 0;  // c's candidate
    for (uint32_t n : c.count) {
      uint32_t* first_face = &L.face[MTX_LOCATE_FACE_STRIDE * cell];
      float* first_map = &L.map[MTX_LOCATE_MAP_STRIDE * cell];
      if (n == 0) {
        for (int r = 0; r < 3; ++r) first_face[1 + r] = face_vertices.empty() ? 0u : face_vertices[r];
        std::fill(first_map, first_map + MTX_LOCATE_MAP_STRIDE, 1.f / 3.f);
      } else {
        std::copy_n(&c.face[MTX_LOCATE_FACE_STRIDE * k], MTX_LOCATE_FACE_STRIDE, first_face);
        std::copy_n(&c.map[MTX_LOCATE_MAP_STRIDE * k], MTX_LOCATE_MAP_STRIDE, first_map);
        ++k;
      }
      L.cells.push_back(static_cast<uint32_t>(L.face.size() / MTX_LOCATE_FACE_STRIDE));
      for (uint32_t m = 1; m < n; ++m, ++k) {
        L.face.insert(L.face.end(), &c.face[MTX_LOCATE_FACE_STRIDE * k], &c.face[MTX_LOCATE_FACE_STRIDE * (k + 1)]);
        L.map.insert(L.map.end(), &c.map[MTX_LOCATE_MAP_STRIDE * k], &c.map[MTX_LOCATE_MAP_STRIDE * (k + 1)]);
      }
      ++cell;
    }
  }
  L.cells.push_back(static_cast<uint32_t>(L.face.size() / MTX_LOCATE_FACE_STRIDE));
  return L;
}

}  // namespace moldtex
