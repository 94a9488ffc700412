/* kernels.cl — the OpenCL program. The host prepends the shared sources (portable.h,
 * constants.h, rng.h, walk.h, momas.h, field.h, pde.h, reaction.h, intrinsic_locate.h,
 * intrinsic_lattice.h, texel_sampling.h, continuous.h: the same the CPU backend compiles
 * as C++), so these kernels only unpack buffers and call the shared functions. The host
 * builds it once per feature combination in use (-DMTX_FOOD, -DMTX_FIELDS, -DMTX_SPECIES;
 * see momas.h), so the agent kernel carries only the code it runs. */

/* Agent i's walker from the structure-of-arrays buffers (the third barycentric is
 * 1 - b1 - b2), and back. */
static inline mtx_walker load_walker(__global const uint* triangle, __global const float* b1,
                                     __global const float* b2, __global const float* hx,
                                     __global const float* hy, uint i) {
  mtx_walker w;
  w.triangle = triangle[i];
  w.bary[1] = b1[i];
  w.bary[2] = b2[i];
  w.bary[0] = 1.0f - w.bary[1] - w.bary[2];
  w.heading.x = hx[i];
  w.heading.y = hy[i];
  return w;
}

static inline void store_walker(const mtx_walker* w, __global uint* triangle, __global float* b1,
                                __global float* b2, __global float* hx, __global float* hy, uint i) {
  triangle[i] = w->triangle;
  b1[i] = w->bary[1];
  b2[i] = w->bary[2];
  hx[i] = w->heading.x;
  hy[i] = w->heading.y;
}

__kernel void momas_agents(__global const mtx_frame* frames, __global const uint* adjacency,
                           __global const float* corner_uvs, __global const uchar* classes,
                           __global const float* pheromone, __global const float* field,
                           __global uchar* marks, __global uint* triangle, __global float* b1,
                           __global float* b2, __global float* hx, __global float* hy,
                           __global const uchar* species, __global float* hunger,
                           __global const float* frame3d, __global const float* food,
                           __global uint* eaters, __global const float* texels_per_unit,
                           __global const int* texel_island, __global const uint* island,
                           __global const uchar* interior_reach, __global const float* unfolded,
                           const mtx_momas_constants k, const uint count) {
  const uint i = get_global_id(0);
  if (i >= count) return;
  mtx_surface_tables s;
  s.frames = frames;
  s.adjacency = adjacency;
  s.corner_uvs = corner_uvs;
  s.classes = classes;
  s.frame3d = frame3d;
  s.food = food;
  s.eaters = eaters;
  s.texels_per_unit = texels_per_unit;
  s.island = island;
  s.texel_island = texel_island;
  s.interior_bits = 0;
  s.interior_reach = interior_reach;
  s.unfolded = unfolded;
  s.sole_reach = 0;
  s.face_vertices = 0;
  s.locator_grid = 0;
  s.locator_cells = 0;
  s.locator_face = 0;
  s.locator_map = 0;
  s.locator_next = 0;
  s.locator_across = 0;
  s.vertex_cells = 0u;
  s.lattice = 0;
  s.lattice_field = 0;
  mtx_walker w = load_walker(triangle, b1, b2, hx, hy, i);
  /* Per-agent hunger and species are loaded only by the variants that use them. */
  float h = MTX_FOOD ? hunger[i] : 0.0f;
#if defined(MTX_SPECIES) && MTX_SPECIES == 1
  const uint sp = 0;
#else
  const uint sp = species[i];
#endif
  mtx_momas_agent_step(s, pheromone, field, marks, &w, &h, sp, (ulong)i, &k);
  if (MTX_FOOD) hunger[i] = h;
  store_walker(&w, triangle, b1, b2, hx, hy, i);
}

/* pheromone and marks hold `planes` planes of `texels`; plane p gets deposit[p] where
 * marked, on island texels only (agents mark whatever texel they stand on). */
__kernel void apply_deposits(__global float* pheromone, __global uchar* marks, __global const uchar* classes,
                             const float4 deposit, const uint texels, const uint planes) {
  const uint i = get_global_id(0);
  if (i >= texels * planes || !marks[i]) return;
  const uint p = i / texels;
  const float d = p == 0 ? deposit.x : (p == 1 ? deposit.y : (p == 2 ? deposit.z : deposit.w));
  if (classes[i - p * texels] == MTX_TEXEL_INSIDE) pheromone[i] = fmax(pheromone[i], d);
  marks[i] = 0;
}

/* Gutter texels copy island texels; the two sets are disjoint, so no write races. */
__kernel void fill_gutter(__global float* pheromone, __global const uint* gutter_texel,
                          __global const uint* gutter_source, const uint count,
                          const uint texels, const uint planes) {
  const uint i = get_global_id(0);
  if (i >= count) return;
  for (uint p = 0; p < planes; ++p)
    pheromone[p * texels + gutter_texel[i]] = pheromone[p * texels + gutter_source[i]];
}

__kernel void diffuse_evaporate(__global const float* in, __global float* out,
                                __global const uchar* classes, const int width,
                                const int height, const float mix, const float evaporation,
                                const uint planes) {
  const int x = get_global_id(0), y = get_global_id(1);
  if (x >= width || y >= height) return;
  const uint i = (uint)y * (uint)width + (uint)x;
  const uint texels = (uint)width * (uint)height;
  for (uint p = 0; p < planes; ++p)
    out[p * texels + i] =
        classes[i] == MTX_TEXEL_INSIDE
            ? mtx_diffuse_evaporate_texel(in + p * texels, classes, x, y, width, height, mix,
                                          evaporation)
            : 0.0f;
}

/* Surface diffusion (see domain/surface_diffusion.h): one pass over every texel with its
 * grid neighbours; coef holds ax, ay per triangle. */
__kernel void surface_diffuse(__global const float* in, __global float* out,
                              __global const uchar* classes, __global const int* texel_triangle,
                              __global const float* coef, const int width, const int height,
                              const float evaporation, const uint planes) {
  const int x = get_global_id(0), y = get_global_id(1);
  if (x >= width || y >= height) return;
  const uint i = (uint)y * (uint)width + (uint)x;
  const uint texels = (uint)width * (uint)height;
  const int t = texel_triangle[i];
  for (uint p = 0; p < planes; ++p) {
    __global const float* src = in + p * texels;
    if (classes[i] != MTX_TEXEL_INSIDE) {
      out[p * texels + i] = 0.0f;
      continue;
    }
    const float u = src[i];
    out[p * texels + i] = mtx_surface_diffuse(
        u, x > 0 ? src[i - 1] : u, x + 1 < width ? src[i + 1] : u, y > 0 ? src[i - width] : u,
        y + 1 < height ? src[i + width] : u, coef[2 * t], coef[2 * t + 1], evaporation);
  }
}

/* The same for the texels at seams, with their neighbours across the seam. */
__kernel void seam_diffuse(__global const float* in, __global float* out,
                           __global const uint* seam_texel, __global const uint* seam_neighbour,
                           __global const int* texel_triangle, __global const float* coef,
                           const uint count, const uint texels, const float evaporation,
                           const uint planes) {
  const uint j = get_global_id(0);
  if (j >= count) return;
  const uint i = seam_texel[j];
  __global const uint* n = seam_neighbour + 4 * j;
  const int t = texel_triangle[i];
  for (uint p = 0; p < planes; ++p) {
    __global const float* src = in + p * texels;
    out[p * texels + i] = mtx_surface_diffuse(src[i], src[n[0]], src[n[1]], src[n[2]], src[n[3]],
                                              coef[2 * t], coef[2 * t + 1], evaporation);
  }
}

/* Extra pass `pass` of the small texels: new values into scratch (count per plane)... */
__kernel void fine_diffuse(__global const float* field, __global float* scratch,
                           __global const uint* fine_texel, __global const uint* fine_neighbour,
                           __global const float* fine_coef, __global const uint* fine_extra,
                           const uint pass, const uint count, const uint texels,
                           const uint planes) {
  const uint j = get_global_id(0);
  if (j >= count) return;
  const uint i = fine_texel[j];
  __global const uint* n = fine_neighbour + 4 * j;
  for (uint p = 0; p < planes; ++p) {
    __global const float* src = field + p * texels;
    scratch[p * count + j] =
        fine_extra[j] < pass ? src[i]
                             : mtx_surface_diffuse(src[i], src[n[0]], src[n[1]], src[n[2]], src[n[3]],
                                                   fine_coef[2 * j], fine_coef[2 * j + 1], 0.0f);
  }
}

/* ... then written back. */
__kernel void fine_scatter(__global float* field, __global const float* scratch,
                           __global const uint* fine_texel, const uint count, const uint texels,
                           const uint planes) {
  const uint j = get_global_id(0);
  if (j >= count) return;
  for (uint p = 0; p < planes; ++p) field[p * texels + fine_texel[j]] = scratch[p * count + j];
}

/* Continuous model: one forward-Euler sub-step of the diffusion-decay PDE on the texel
 * Laplacian (domain/texel_laplacian.h), one CSR row (cell) per work-item, every species plane. Reads only
 * `in`, so rows are independent; decay is exp(-r_dec dt) on a step's last sub-step, else
 * 1. */
__kernel void pde_diffuse(__global const uint* rows, __global const uint* start,
                          __global const uint* col, __global const float* weight,
                          __global const float* area, __global const float* in,
                          __global float* out, const float h, const float decay,
                          const uint count, const uint texels, const uint planes) {
  const uint r = get_global_id(0);
  if (r >= count) return;
  for (uint p = 0; p < planes; ++p)
    out[p * texels + rows[r]] =
        mtx_diffuse_cell(rows, start, col, weight, area, in + p * texels, r, h, decay);
}

/* Local time stepping (shared/pde.h, domain/texel_laplacian.h LocalSteppingPlan), every
 * species plane: fine cells start from the coarse sub-step's values with no inflow yet
 * (cur: `count` values per plane; flux: `entries` compact entries per plane); */
__kernel void pde_fine_start(__global const uint* fine_cell, __global const uint* fine_start,
                             __global const float* in, __global float* cur, __global float* flux,
                             const uint count, const uint texels, const uint entries, const uint planes) {
  const uint f = get_global_id(0);
  if (f >= count) return;
  for (uint p = 0; p < planes; ++p) {
    cur[p * count + f] = in[p * texels + fine_cell[f]];
    for (uint e = fine_start[f]; e < fine_start[f + 1]; ++e) flux[p * entries + e] = 0.0f;
  }
}

/* one fine sub-step of the fine cells (cur -> next); */
__kernel void pde_fine_diffuse(__global const uint* fine_start, __global const uint* fine_nbr,
                               __global const float* fine_weight, __global const float* fine_area,
                               __global const float* frozen, __global const float* cur,
                               __global float* next, __global float* flux, const float h,
                               const uint count, const uint texels, const uint entries,
                               const uint planes) {
  const uint f = get_global_id(0);
  if (f >= count) return;
  for (uint p = 0; p < planes; ++p)
    next[p * count + f] = mtx_fine_cell(fine_start, fine_nbr, fine_weight, fine_area, frozen + p * texels,
                                        cur + p * count, flux + p * entries, f, h);
}

/* then the coarse cells take their sub-step less what the fine ones drew, */
__kernel void pde_coarse_diffuse(__global const uint* rows, __global const uint* start,
                                 __global const uint* col, __global const float* weight,
                                 __global const float* area, __global const uchar* step_class,
                                 __global const uint* link, __global const float* in,
                                 __global const float* flux, __global float* out, const float h,
                                 const float decay, const uint count, const uint texels,
                                 const uint entries, const uint planes) {
  const uint r = get_global_id(0);
  if (r >= count) return;
  const uint i = rows[r];
  if (step_class[i] == MTX_STEP_FINE) return;
  for (uint p = 0; p < planes; ++p)
    out[p * texels + i] = mtx_coarse_cell(rows, start, col, weight, area, step_class, link, in + p * texels,
                                          flux + p * entries, r, h, decay);
}

/* and the fine ones their final value. */
__kernel void pde_fine_finish(__global const uint* fine_cell, __global const float* cur,
                              __global float* out, const float decay, const uint count,
                              const uint texels, const uint planes) {
  const uint f = get_global_id(0);
  if (f >= count) return;
  for (uint p = 0; p < planes; ++p) out[p * texels + fine_cell[f]] = cur[p * count + f] * decay;
}

/* The continuous model's agents (shared/continuous.h); lives holds 4 floats per agent
 * (clock, age, exposure, threshold), sums one fixed-point plane per species. */
__kernel void continuous_agents(__global const mtx_frame* frames, __global const uint* adjacency,
                                __global const float* corner_uvs, __global const uchar* classes,
                                __global const float* u, __global const float* field,
                                __global int* sums, __global uint* triangle, __global float* b1,
                                __global float* b2, __global float* hx, __global float* hy,
                                __global const uchar* species, __global float4* lives,
                                __global const float* texels_per_unit, __global const uint* island,
                                __global const int* texel_island, __global const uint* interior_bits,
                                __global const float* unfolded, __global const float* alias_prob, __global const uint* alias_index,
                                __global const float* bias, __global const float* maps,
                                __global const float* spawn_max, __global const uint* face_vertices,
                                __global const uint* locator_grid, __global const uint* locator_cells,
                                __global const uint* locator_face, __global const float* locator_map,
                                __global const uint* locator_next, __global const float* locator_across,
                                __global const uint* lattice, __global const float* lattice_field,
                                const uint vertex_cells, const mtx_continuous_constants k,
                                const uint count) {
  const uint i = get_global_id(0);
  if (i >= count) return;
  mtx_surface_tables s;
  s.frames = frames;
  s.adjacency = adjacency;
  s.corner_uvs = corner_uvs;
  s.classes = classes;
  s.frame3d = 0;
  s.food = 0;
  s.eaters = 0;
  s.texels_per_unit = texels_per_unit;
  s.island = island;
  s.texel_island = texel_island;
  s.interior_bits = interior_bits;
  s.interior_reach = 0;
  s.unfolded = unfolded;
  s.sole_reach = 0;
  s.face_vertices = face_vertices;
  s.locator_grid = locator_grid;
  s.locator_cells = locator_cells;
  s.locator_face = locator_face;
  s.locator_map = locator_map;
  s.locator_next = locator_next;
  s.locator_across = locator_across;
  s.vertex_cells = vertex_cells;
  /* The intrinsic domain reads and deposits at its lattice's nodes (u and sums are
   * planes of nodes then). */
  s.lattice = vertex_cells ? lattice : 0;
  s.lattice_field = vertex_cells ? lattice_field : 0;
  mtx_walker w = load_walker(triangle, b1, b2, hx, hy, i);
  const float4 l = lives[i];
  mtx_agent_life life;
  life.clock = l.x;
  life.age = l.y;
  life.exposure = l.z;
  life.threshold = l.w;
#if defined(MTX_SPECIES) && MTX_SPECIES == 1
  const uint sp = 0;
#else
  const uint sp = species[i];
#endif
  mtx_continuous_agent_step(s, u, field, sums, alias_prob, alias_index, bias, maps, spawn_max, &w, &life, sp,
                            (ulong)i, &k);
  store_walker(&w, triangle, b1, b2, hx, hy, i);
  lives[i] = (float4)(life.clock, life.age, life.exposure, life.threshold);
}

/* The intrinsic domain's lattice (shared/intrinsic_lattice.h): the vertex values onto
 * the nodes before the agents' step, the nodes' deposits on to the vertices after it. */
__kernel void lattice_gather(__global const float* u, __global const uint* vertex, __global const float* weight,
                             __global float* nodes, const uint count, const uint vertices, const uint planes) {
  const uint n = get_global_id(0);
  if (n < count) mtx_lattice_gather_node(u, vertex, weight, nodes, n, count, vertices, planes);
}

__kernel void lattice_scatter(__global int* node_sums, __global int* sums, __global const uint* vertex,
                              __global const float* weight, const uint count, const uint vertices,
                              const uint planes) {
  const uint n = get_global_id(0);
  if (n < count) mtx_lattice_scatter_node(node_sums, sums, vertex, weight, n, count, vertices, planes, 0);
}

/* Deposit sums of the cells become concentration, every plane: u += sums * amount /
 * area; sums = 0. */
__kernel void deposits_to_concentration(__global float* u, __global int* sums,
                                        __global const uint* rows, __global const float* area,
                                        const float amount, const uint count, const uint texels,
                                        const uint planes) {
  const uint r = get_global_id(0);
  if (r >= count) return;
  const uint i = rows[r];
  if (!(area[i] > 0.0f)) return;
  for (uint p = 0; p < planes; ++p) {
    const int q = sums[p * texels + i];
    if (q == 0) continue;
    u[p * texels + i] += mtx_deposit_concentration(q, amount, area[i]);
    sums[p * texels + i] = 0;
  }
}

/* The write stimulus (moldtex_sim_set_map) of every cell into every plane: plane p gains
 * write[i] * amount.sN (its r_dec U dt (e^k - 1) / k), never going below 0. */
__kernel void write_stimulus(__global float* u, __global const uint* rows, __global const float* write,
                             const float4 amount, const uint count, const uint texels, const uint planes) {
  const uint r = get_global_id(0);
  if (r >= count) return;
  const uint i = rows[r];
  const float a[4] = {amount.x, amount.y, amount.z, amount.w};
  for (uint p = 0; p < planes; ++p) u[p * texels + i] = mtx_write_stimulus(u[p * texels + i], write[i], a[p]);
}

/* The decay map: every plane's cell i times factor[i]. */
__kernel void scale_cells(__global float* u, __global const uint* rows, __global const float* factor,
                          const uint count, const uint texels, const uint planes) {
  const uint r = get_global_id(0);
  if (r >= count) return;
  const uint i = rows[r];
  for (uint p = 0; p < planes; ++p) u[p * texels + i] *= factor[i];
}

/* Gray-Scott reaction-diffusion (shared/reaction.h): one sub-step of every cell, planes
 * V (0) and U (1) of `in` into `out`. Reads only `in`, so cells are independent. */
__kernel void gray_scott_substep(__global const uint* rows, __global const uint* start,
                                 __global const uint* col, __global const float* weight,
                                 __global const float* area, __global const float* rate,
                                 __global const float* in, __global float* out,
                                 const float h, const float du,
                                 const float dv, const float feed, const float kill,
                                 __global const float* feed_map, __global const float* kill_map,
                                 const uint use_feed_map, const uint use_kill_map,
                                 const uint count, const uint texels) {
  const uint r = get_global_id(0);
  if (r >= count) return;
  mtx_gray_scott_cell(rows, start, col, weight, area, rate, in, in + texels, out, out + texels, r, h, du, dv,
                      feed, kill, feed_map, kill_map, use_feed_map, use_kill_map);
}
