// The intrinsic domain (issue 11, layton-intrinsic-slime.md §3.1): concentrations live at
// the vertices of an intrinsic Delaunay triangulation of the mesh (intrinsic/), refined
// until no triangle's circumradius exceeds a bound. No UV layout enters the simulation:
// no seams, no UV distortion, no dependence on how the artist's mesh is triangulated.
//
// What the simulation needs from it, all built once per mesh and bound:
//  * a locator (domain/intrinsic_locator.h): any point of the input mesh found on the
//    intrinsic faces (shared/texel_sampling.h, vertex_cells: the three vertex hats of the
//    face under it); parameter maps and the texel map use it;
//  * a sampling lattice (domain/intrinsic_lattice.h): agents walk the input mesh as on
//    the texture domain and read and deposit at nodes of their own input triangle, found
//    by arithmetic; the vertex values go onto the nodes before the agents' step and the
//    nodes' deposits onto the vertices after it;
//  * the diffusion operator: the cotangent Laplacian with barycentric lumped mass, as a
//    cell graph (domain/texel_laplacian.h) whose cells are the vertices, so both
//    integrators, maps and Gray-Scott run on it unchanged;
//  * the way into the texture: each island texel located once on the intrinsic
//    triangulation (face + barycentrics), so a frame is a gather; the gutter is filled as
//    on the texture domain;
//
// Why agents walk the input mesh and not the intrinsic faces (the paper's way): see
// domain/intrinsic_locator.h (the benchmark decided: 7x faster).
#pragma once
#include <cstdint>
#include <list>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "agents/continuous_rules.h"
#include "agents/parameter_maps.h"
#include "backends/backend.h"
#include "backends/cpu/thread_pool.h"
#include "common/progress.h"
#include "domain/intrinsic_lattice.h"
#include "domain/intrinsic_locator.h"
#include "domain/texel_laplacian.h"
#include "domain/texture_domain.h"
#include "intrinsic/refinement.h"
#include "shared/momas.h"
#include "surface/surface.h"

namespace moldtex {

struct IntrinsicDomain {
  intrinsic::IntrinsicTriangulation tri;
  intrinsic::RefineReport report;
  double bound = 0;          // the circumradius bound it was refined to (mesh units)
  double build_seconds = 0;  // triangulation, operators and texel map

  // The simulation numbers faces and vertices along a space-filling curve (Morton order
  // of their 3D positions), so that agents sorted by face and the PDE's rows touch
  // nearby memory; `tri` keeps the triangulation's own numbering. *_order[new] = old,
  // *_rank[old] = new. Every table below uses the new numbers.
  std::vector<uint32_t> face_order, face_rank, vertex_order, vertex_rank;

  std::vector<uint32_t> face_vertices;  // 3 per intrinsic face, in corner order
  // Per surface triangle: its input face of the triangulation (kInvalid: dropped, a
  // triangle that repeats a vertex).
  std::vector<uint32_t> input_face;
  // Where agents (on the input mesh) read and deposit (shared/intrinsic_locate.h), and
  // the deposit pieces per mesh unit (2 per surface triangle, as texels_per_unit).
  IntrinsicLocator locator;
  std::vector<float> cells_per_unit;
  // Where agents read and deposit: nodes about one intrinsic edge apart on each input
  // triangle (domain/intrinsic_lattice.h), each located once by tracing.
  IntrinsicLattice lattice;

  TexelLaplacian laplacian;  // cells = vertices, area = lumped mass

  // Per texel: the intrinsic face under the texel centre (kNone for texels that are not
  // island cells) and its barycentrics (3 per texel).
  static constexpr uint32_t kNone = 0xffffffffu;
  std::vector<uint32_t> texel_face;
  std::vector<float> texel_bary;
  // Per vertex: the texel under its point on the input mesh (parameter maps and static
  // fields are given per texel and read there).
  std::vector<uint32_t> vertex_texel;

  uint32_t vertex_count() const { return tri.mesh.vertex_count(); }
  // The point on the input mesh of vertex v (new numbering).
  const intrinsic::SurfacePoint& vertex_location(uint32_t v) const { return tri.corr.location[vertex_order[v]]; }
  uint32_t face_count() const { return tri.mesh.face_count(); }
  // The input surface's tables (walk, UVs, bias) with this domain's cells and locator.
  mtx_surface_tables tables(mtx_surface_tables surface) const;
  // tables() with the lattice, where agents read and deposit (their stencils then hold
  // nodes); lattice_field: the static field at the nodes (NULL without one).
  mtx_surface_tables agent_tables(mtx_surface_tables surface, const float* lattice_field) const;
  // Island texels of `texels` (width * height) from the vertex values (vertex_count);
  // other texels are left as they are (the caller fills the gutter).
  void gather(const float* values, float* texels, ThreadPool& pool) const;
  // Per vertex, the value of the texel under it.
  std::vector<float> sample_texels(const float* texels) const;
  // `planes` planes of vertex values shown in texture planes of `texture` (outside the
  // islands 0, the gutter filled).
  void show(const float* values, float* texels, uint32_t planes, const TextureDomain& texture, ThreadPool& pool) const;
  // The vertex values a backend takes from a state (SimState::cells, plus any change made
  // to the texture planes since they were shown there, e.g. a brush dab), or from texture
  // planes alone (each vertex its texel's value).
  std::vector<float> values_from_state(const SimState& state, uint32_t planes, const TextureDomain& texture,
                                       ThreadPool& pool) const;
  // The simulation's per-texel maps read at the vertices: the agent planes, the PDE's and
  // Gray-Scott's maps; the spawn map's per-triangle tables stay (agents respawn on the
  // input mesh).
  ParameterMaps vertex_maps(const ParameterMaps& maps, size_t texels) const;
  // A point (and heading) of the input mesh (surface triangle numbering) on the
  // intrinsic faces (the domain's numbering), and back: the correspondence, for tests
  // and tools (agents stay on the input mesh).
  Walker to_intrinsic(const Walker& w) const;
  Walker to_input(const Walker& w) const;
  size_t bytes() const;
};

// A backend's copy of the simulation's maps read at the vertices (vertex_maps), remade
// when the maps change.
class VertexMaps {
 public:
  const ParameterMaps& of(const IntrinsicDomain& domain, const ParameterMaps& maps, size_t texels);
  size_t bytes() const { return maps_.agent_planes.capacity() * 4; }

 private:
  ParameterMaps maps_;
  const void* source_ = nullptr;
  uint64_t version_ = ~0ull;
};

// The default bound: the mean 3D spacing of the island texels, so that the intrinsic
// triangulation has about as many vertices as the texture has island texels and both
// domains resolve the same detail.
double default_intrinsic_bound(const TextureDomain& domain);

// The last few domains built, most recent first, keyed by the mesh (its fingerprint), the
// texture size, the bound and the insertion limit, so that a new simulation on the same
// mesh does not rebuild it (Reset in the add-on makes one when the resolution or the model
// changes). Thread-safe. Each context (moldtex_context) owns one; simulations made
// without a context share the process's default one.
class IntrinsicDomainCache {
 public:
  static constexpr size_t kEntries = 2;
  std::shared_ptr<const IntrinsicDomain> find(uint64_t fingerprint, uint32_t width, uint32_t height, double bound,
                                              uint64_t max_insertions);
  void put(uint64_t fingerprint, uint32_t width, uint32_t height, double bound, uint64_t max_insertions,
           std::shared_ptr<const IntrinsicDomain> domain);
  void clear();
  size_t size() const;

 private:
  struct Entry {
    uint64_t fingerprint;
    uint32_t width, height;
    double bound;
    uint64_t max_insertions;
    std::shared_ptr<const IntrinsicDomain> domain;
  };
  mutable std::mutex mutex_;
  std::list<Entry> entries_;
};

// The cache of simulations made without a context (the process's default context).
const std::shared_ptr<IntrinsicDomainCache>& default_intrinsic_cache();

// Builds the domain (throws moldtex::Error for meshes it refuses: non-manifold, or a
// refinement that cannot finish within max_insertions, 0 = automatic), or takes it from
// `cache`, where it is then kept.
// from_cache (optional) says whether it came from the cache. progress (optional) reports
// the build's stage (moldtex_build_stage) and lets another thread cancel it
// (MOLDTEX_ERROR_CANCELLED; nothing is cached then).
std::shared_ptr<const IntrinsicDomain> intrinsic_domain_for(const Surface& surface, const TextureDomain& domain,
                                                            double bound, uint64_t max_insertions,
                                                            ThreadPool& pool, IntrinsicDomainCache& cache,
                                                            bool* from_cache = nullptr,
                                                            WorkProgress* progress = nullptr);

// Vertices per bound^2 of area the refinement ends with, for progress estimates: 0.66-0.69
// on tori of 4 k and 100 k triangles at the default bound for 1024^2 (Chew's argument
// allows 0.4-1.6).
constexpr double kExpectedVerticesPerBound2 = 0.68;

}  // namespace moldtex
