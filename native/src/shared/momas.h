/* momas.h — MoMaS agent behaviour (momas-paper.md Algorithm 1, lines 9-23) for one
 * agent: sense at three sensors traced over the surface, steer toward the strongest,
 * move in substeps, mark deposits. Reads the pheromone only; the marks are written with
 * the same value by every writer, so the order of writers cannot change the result. */
#ifndef MOLDTEX_SHARED_MOMAS_H
#define MOLDTEX_SHARED_MOMAS_H

#ifndef __OPENCL_C_VERSION__
#include "shared/angle.h"
#include "shared/constants.h"
#include "shared/portable.h"
#include "shared/rng.h"
#include "shared/walk.h"
#endif

/* Compile-time specialisation. The C++ build keeps every feature in and decides per step
 * from the constants. The OpenCL backend builds one program per combination in use, with
 * -DMTX_FOOD=0 while food with hunger is off (k->hunger_step <= 0), -DMTX_FIELDS=0 while
 * there are no fields (k->has_fields == 0) and -DMTX_SPECIES=n (n == k->species_count),
 * so its agent kernel carries only the code it runs. Each switch only drops work whose
 * run-time condition is false, so every variant computes the same results. */
#ifndef MTX_FOOD
#define MTX_FOOD 1
#endif
#ifndef MTX_FIELDS
#define MTX_FIELDS 1
#endif
#ifdef MTX_SPECIES
#define MTX_SPECIES_COUNT(k) MTX_CAST(mtx_u32, MTX_SPECIES)
#else
#define MTX_SPECIES_COUNT(k) ((k)->species_count)
#endif

MTX_BEGIN_NAMESPACE

/* Read-only surface and layout tables, as both backends hold them. */
typedef struct mtx_surface_tables {
  MTX_GLOBAL const mtx_frame* frames;
  MTX_GLOBAL const mtx_u32* adjacency;
  MTX_GLOBAL const float* corner_uvs; /* 6 per triangle */
  MTX_GLOBAL const mtx_u8* classes;   /* per texel */
  /* Food with hunger (read only when k->hunger_step > 0). frame3d: 9 per triangle, the
   * 3D position of corner 0 and the unit 3D x and y axes of the triangle's frame. food:
   * 4 per source with food left (x, y, z, strength); eaters: one counter per source. */
  MTX_GLOBAL const float* frame3d;
  MTX_GLOBAL const float* food;
  MTX_GLOBAL mtx_u32* eaters;
  /* Surface units (k->surface_mode): texels per mesh unit along x and y, 2 per triangle
   * (W / |dP/du|, H / |dP/dv|), and the UV island of each triangle, so a footprint stays
   * on its own island. */
  MTX_GLOBAL const float* texels_per_unit;
  MTX_GLOBAL const mtx_u32* island;
  /* The island of each island texel, -1 elsewhere (the continuous model's stencils, the
   * MoMaS footprints of surface units). */
  MTX_GLOBAL const int* texel_island;
  MTX_GLOBAL const mtx_u32* interior_bits; /* see TextureDomain::interior_bits */
  /* The intrinsic domain (domain/intrinsic_domain.h; vertex_cells = 1): agents walk the
   * input mesh as on the texture domain, but the cells are the vertices of the intrinsic
   * triangulation: a point is located on an intrinsic face (shared/intrinsic_locate.h:
   * the locator's grid, cells, candidate faces and maps) and reads and deposits through
   * that face's vertices (3 per face here) with its barycentric weights. 0 and NULL on
   * the texture domain. */
  MTX_GLOBAL const mtx_u32* face_vertices;
  MTX_GLOBAL const mtx_u32* locator_grid;
  MTX_GLOBAL const mtx_u32* locator_cells;
  MTX_GLOBAL const mtx_u32* locator_face;
  MTX_GLOBAL const float* locator_map;
  MTX_GLOBAL const mtx_u32* locator_next;
  MTX_GLOBAL const float* locator_across;
  mtx_u32 vertex_cells;
  /* Where agents read and deposit on the intrinsic domain (shared/intrinsic_lattice.h):
   * the lattice's 2 words per input triangle (first node, G), and the static field at the
   * nodes (NULL without fields). With `lattice` set, stencils hold nodes, not vertices;
   * NULL on the texture domain. */
  MTX_GLOBAL const mtx_u32* lattice;
  MTX_GLOBAL const float* lattice_field;
  /* MoMaS in surface units: per texel the largest r (at most 255) such that the
   * (2r + 1)^2 block around it holds texels of its own island only (0 off the islands;
   * TextureDomain::interior_reach), so a footprint box within that block needs no test
   * per texel. NULL: every footprint tests each texel. */
  MTX_GLOBAL const mtx_u8* interior_reach;
  /* Each edge's neighbour unfolded into the triangle's frame (shared/walk.h,
   * MTX_UNFOLDED_FLOATS): a sensor trace that crosses a few edges is located without a
   * walk (mtx_trace_unfolded). NULL: every trace that leaves its triangle walks. */
  MTX_GLOBAL const float* unfolded;
  /* MoMaS in surface units, the sixteen CPU lanes only (agents/momas_lanes16.cpp): per
   * texel 0, or 1 + the interior reach counted over texels that are their island's alone
   * (TextureDomain::sole_reach). NULL elsewhere. */
  MTX_GLOBAL const mtx_u8* sole_reach;
} mtx_surface_tables;

/* The texel holding the point (x, y) in texels, clamped to the texture. */
MTX_FN mtx_u32 mtx_texel_at_point(float x, float y, mtx_u32 width, mtx_u32 height) {
  int ix = MTX_CAST(int, x), iy = MTX_CAST(int, y);
  ix = ix < 0 ? 0 : (ix >= MTX_CAST(int, width) ? MTX_CAST(int, width) - 1 : ix);
  iy = iy < 0 ? 0 : (iy >= MTX_CAST(int, height) ? MTX_CAST(int, height) - 1 : iy);
  return MTX_CAST(mtx_u32, iy) * width + MTX_CAST(mtx_u32, ix);
}

MTX_FN mtx_u32 mtx_texel_of_uv(float u, float v, mtx_u32 width, mtx_u32 height) {
  return mtx_texel_at_point(u * MTX_CAST(float, width), v * MTX_CAST(float, height), width, height);
}

MTX_FN mtx_u32 mtx_walker_texel(MTX_GLOBAL const float* corner_uvs, const mtx_walker* w,
                                mtx_u32 width, mtx_u32 height) {
  MTX_GLOBAL const float* uv = corner_uvs + 6 * w->triangle;
  float u = w->bary[0] * uv[0] + w->bary[1] * uv[2] + w->bary[2] * uv[4];
  float v = w->bary[0] * uv[1] + w->bary[1] * uv[3] + w->bary[2] * uv[5];
  return mtx_texel_of_uv(u, v, width, height);
}

/* The texel under walker w, as mtx_walker_texel, and the walker's point in texels. */
MTX_FN mtx_u32 mtx_walker_texel_at(MTX_GLOBAL const float* corner_uvs, const mtx_walker* w, mtx_u32 width,
                                   mtx_u32 height, float* x, float* y) {
  MTX_GLOBAL const float* uv = corner_uvs + 6 * w->triangle;
  const float u = w->bary[0] * uv[0] + w->bary[1] * uv[2] + w->bary[2] * uv[4];
  const float v = w->bary[0] * uv[1] + w->bary[1] * uv[3] + w->bary[2] * uv[5];
  *x = u * MTX_CAST(float, width);
  *y = v * MTX_CAST(float, height);
  return mtx_texel_of_uv(u, v, width, height);
}

/* Texels per plane: pheromone and deposit marks hold one plane per species. */
MTX_FN mtx_u32 mtx_texel_count(const mtx_momas_constants* k) { return k->width * k->height; }

/* What species `species` senses at `texel`: its attraction-weighted sum of all species'
 * pheromone, plus the static field (obstacles -1e9, attractors). */
MTX_FN float mtx_sensed_value(MTX_GLOBAL const float* pheromone, MTX_GLOBAL const float* field,
                              mtx_u32 texel, mtx_u32 species, const mtx_momas_constants* k) {
  const mtx_u32 texels = mtx_texel_count(k);
  float v = 0.0f;
  for (mtx_u32 p = 0; p < MTX_SPECIES_COUNT(k); ++p)
    v += k->attraction[MTX_MAX_SPECIES * species + p] * pheromone[p * texels + texel];
  if (MTX_FIELDS && k->has_fields) v += field[texel];
  return v;
}

MTX_FN int mtx_is_obstacle(MTX_GLOBAL const float* field, mtx_u32 texel,
                           const mtx_momas_constants* k) {
  return MTX_FIELDS && k->has_fields && field[texel] < MTX_OBSTACLE_THRESHOLD;
}

/* Surface units: the texels within half a length unit of walker w along each texel axis
 * (centres ix + 0.5 in [x - ex, x + ex], at most MTX_MAX_FOOTPRINT_TEXELS each side),
 * clipped to the texture, and its UV island. Returns 0 when that footprint lies within
 * the one texel under the walker (a texel of a unit or more). */
typedef struct mtx_footprint {
  int x0, x1, y0, y1;
  mtx_u32 island;
} mtx_footprint;

/* Clips the texel range of box to the texture. */
MTX_FN void mtx_clip_footprint(mtx_footprint* box, const mtx_momas_constants* k) {
  const int w_ = MTX_CAST(int, k->width), h_ = MTX_CAST(int, k->height);
  box->x0 = box->x0 < 0 ? 0 : box->x0;
  box->y0 = box->y0 < 0 ? 0 : box->y0;
  box->x1 = box->x1 >= w_ ? w_ - 1 : box->x1;
  box->y1 = box->y1 >= h_ ? h_ - 1 : box->y1;
}

/* The texels whose centres ix + 0.5, iy + 0.5 lie in [x - ex, x + ex] x [y - ey, y + ey],
 * clipped to the texture (the island is left to the caller). */
MTX_FN void mtx_centres_within(float x, float y, float ex, float ey, const mtx_momas_constants* k,
                               mtx_footprint* box) {
  box->x0 = mtx_ceil_int(x - ex - 0.5f);
  box->x1 = mtx_floor_int(x + ex - 0.5f);
  box->y0 = mtx_ceil_int(y - ey - 0.5f);
  box->y1 = mtx_floor_int(y + ey - 0.5f);
  mtx_clip_footprint(box, k);
}

/* The footprint around the point (x, y), in texels, on `triangle`. */
MTX_FN int mtx_footprint_box_at(MTX_TABLES s, mtx_u32 triangle, float x, float y,
                                const mtx_momas_constants* k, mtx_footprint* box) {
  MTX_GLOBAL const float* tpu = s.texels_per_unit + 2 * triangle;
  const float ex = mtx_min(0.5f * k->length_unit * tpu[0], MTX_CAST(float, MTX_MAX_FOOTPRINT_TEXELS));
  const float ey = mtx_min(0.5f * k->length_unit * tpu[1], MTX_CAST(float, MTX_MAX_FOOTPRINT_TEXELS));
  if (ex < 0.5f && ey < 0.5f) return 0;
  mtx_centres_within(x, y, ex, ey, k, box);
  box->island = s.island[triangle];
  return 1;
}

/* The footprint around walker w. */
MTX_FN int mtx_footprint_box(MTX_TABLES s, const mtx_walker* w,
                             const mtx_momas_constants* k, mtx_footprint* box) {
  MTX_GLOBAL const float* uv = s.corner_uvs + 6 * w->triangle;
  const float x = (w->bary[0] * uv[0] + w->bary[1] * uv[2] + w->bary[2] * uv[4]) * MTX_CAST(float, k->width);
  const float y = (w->bary[0] * uv[1] + w->bary[1] * uv[3] + w->bary[2] * uv[5]) * MTX_CAST(float, k->height);
  return mtx_footprint_box_at(s, w->triangle, x, y, k, box);
}

/* Does the texel box [x0, x1] x [y0, y1] hold island texels of `island` only? Known
 * without a test per texel where it lies within the block around `texel` (the texel under
 * the walker or probe) that the interior reach says is all of that texel's island, and
 * that island is `island`. 0 where not known (the caller then tests each texel). */
MTX_FN int mtx_box_within_island(MTX_TABLES s, mtx_u32 texel, int x0, int x1, int y0, int y1,
                                 mtx_u32 island, const mtx_momas_constants* k) {
  if (s.interior_reach == 0) return 0;
  const int r = MTX_CAST(int, s.interior_reach[texel]);
  const int cx = MTX_CAST(int, texel % k->width), cy = MTX_CAST(int, texel / k->width);
  return x0 >= cx - r && x1 <= cx + r && y0 >= cy - r && y1 <= cy + r && s.texel_island[texel] == MTX_CAST(int, island);
}

/* Is texel i an island texel of the footprint's island? */
MTX_FN int mtx_in_footprint(MTX_TABLES s, mtx_u32 i, const mtx_footprint* box) {
  return s.texel_island[i] == MTX_CAST(int, box->island); /* -1 off the islands */
}

/* Surface units, single-point sensor: the mean over the texels of the walker's island
 * whose centres lie within half a length unit of the sensor point along each texel axis
 * (the deposit footprint's size), or an obstacle if one lies there: a sensor reads the
 * same 3D neighbourhood at any resolution (a texel of one length unit holds what the
 * mean over the finer texels of that unit holds). */
MTX_FN float mtx_sense_footprint_at(MTX_TABLES s, MTX_GLOBAL const float* pheromone,
                                    MTX_GLOBAL const float* field, mtx_u32 triangle, float x, float y,
                                    mtx_u32 texel, mtx_u32 species, const mtx_momas_constants* k) {
  const float here = mtx_sensed_value(pheromone, field, texel, species, k);
  mtx_footprint box;
  if (!mtx_footprint_box_at(s, triangle, x, y, k, &box) || mtx_is_obstacle(field, texel, k)) return here;
  /* Where the box lies within the block around the probe texel that is all of the
   * walker's island, no test per texel (a load each, most of the reading's time). */
  const int whole = mtx_box_within_island(s, texel, box.x0, box.x1, box.y0, box.y1, box.island, k);
  float sum = here, count = 1.0f;
  /* (Bitwise: where the kernel's build fixes the species count and fields, a constant as
   * an operand of && draws a compiler warning.) */
  if (whole & (MTX_SPECIES_COUNT(k) == 1u) & !(MTX_FIELDS && k->has_fields)) {
    /* The usual reading, one species and no fields: the same sum in the same order
     * without the general reading's per-texel branches. */
    const float a = k->attraction[MTX_MAX_SPECIES * species];
    for (int iy = box.y0; iy <= box.y1; ++iy) {
      const mtx_u32 row = MTX_CAST(mtx_u32, iy) * k->width;
      for (int ix = box.x0; ix <= box.x1; ++ix) {
        const mtx_u32 i = row + MTX_CAST(mtx_u32, ix);
        if (i == texel) continue;
        sum += a * pheromone[i];
        count += 1.0f;
      }
    }
    return sum / count;
  }
  for (int iy = box.y0; iy <= box.y1; ++iy)
    for (int ix = box.x0; ix <= box.x1; ++ix) {
      const mtx_u32 i = MTX_CAST(mtx_u32, iy) * k->width + MTX_CAST(mtx_u32, ix);
      if (i == texel || (!whole && !mtx_in_footprint(s, i, &box))) continue;
      const float v = mtx_sensed_value(pheromone, field, i, species, k);
      if (mtx_is_obstacle(field, i, k)) return v;
      sum += v;
      count += 1.0f;
    }
  return sum / count;
}

/* ... or around walker w. */
MTX_FN float mtx_sense_footprint(MTX_TABLES s, MTX_GLOBAL const float* pheromone,
                                 MTX_GLOBAL const float* field, const mtx_walker* w,
                                 mtx_u32 texel, mtx_u32 species, const mtx_momas_constants* k) {
  float x = 0.0f, y = 0.0f;
  mtx_walker_texel_at(s.corner_uvs, w, k->width, k->height, &x, &y);
  return mtx_sense_footprint_at(s, pheromone, field, w->triangle, x, y, texel, species, k);
}

/* An agent's three sensor probes (left, front, right): where each trace over the surface
 * ends (its triangle and its point in texels) and the texel there. Computed apart from
 * the reading (mtx_momas_agent_finish), so a backend can trace a batch of agents first
 * and fetch their texels together. */
typedef struct mtx_momas_probes {
  mtx_u32 triangle[3];
  float x[3], y[3];
  mtx_u32 texel[3];
  mtx_u32 here;      /* the texel under the agent */
  float clearance;   /* the agent's distance to its triangle's edges (mtx_edge_clearance) */
} mtx_momas_probes;

MTX_FN void mtx_momas_probe(MTX_TABLES s, const mtx_walker* w, mtx_u32 species,
                            const mtx_momas_constants* k, mtx_momas_probes* p) {
  const float c = k->sensor_cos[species], sn = k->sensor_sin[species];
  const float length = k->sensor_length[species];
  float x, y; /* the agent's point in texels */
  p->here = mtx_walker_texel_at(s.corner_uvs, w, k->width, k->height, &x, &y);
  p->clearance = mtx_edge_clearance(s.frames, w);
  if (k->coast) { /* a step without sensing (mtx_momas_constants.coast) */
    for (int i = 0; i < 3; ++i) {
      p->triangle[i] = w->triangle;
      p->texel[i] = p->here;
      p->x[i] = x;
      p->y[i] = y;
    }
    return;
  }
  if (mtx_walk_stays_inside(p->clearance, length)) {
    /* The usual case: all three traces end inside the agent's triangle, where texel
     * coordinates are an affine map of the frame's: each end is the agent's point plus
     * `length` times its heading mapped by that map's Jacobian, J = dUV/dq scaled to
     * texels (d(b1, b2)/dq = [[1/a, -bx/(a by)], [0, 1/by]]). */
    MTX_GLOBAL const mtx_frame* f = s.frames + w->triangle;
    MTX_GLOBAL const float* uv = s.corner_uvs + 6 * w->triangle;
    const float width = MTX_CAST(float, k->width), height = MTX_CAST(float, k->height);
    const float du1 = (uv[2] - uv[0]) * width, dv1 = (uv[3] - uv[1]) * height;
    const float du2 = (uv[4] - uv[0]) * width, dv2 = (uv[5] - uv[1]) * height;
    const float jxx = du1 * f->inv_a, jyx = dv1 * f->inv_a;
    const float jxy = (du2 - f->bx * jxx) * f->inv_by, jyy = (dv2 - f->bx * jyx) * f->inv_by;
    for (int i = 0; i < 3; ++i) {
      const mtx_vec2 h = i == 1 ? w->heading : mtx_rotate(w->heading, c, i == 0 ? sn : -sn);
      p->triangle[i] = w->triangle;
      p->x[i] = x + length * (jxx * h.x + jxy * h.y);
      p->y[i] = y + length * (jyx * h.x + jyy * h.y);
      p->texel[i] = mtx_texel_at_point(p->x[i], p->y[i], k->width, k->height);
    }
    return;
  }
  /* Otherwise each trace on its own: located through the unfolded neighbours where it
   * can be, walked where not. A trace ends where it meets an open boundary, and the
   * sensor reads there (as Layton et al. do): a bounced trace would read the mirror
   * image of the agent's own neighbourhood, and trails along the wall would merge with
   * their images. */
  for (int i = 0; i < 3; ++i) {
    mtx_walker at = *w;
    if (i != 1) at.heading = mtx_rotate(w->heading, c, i == 0 ? sn : -sn);
    mtx_walk_trace(s.frames, s.adjacency, s.unfolded, &at, length, MTX_BOUNDARY_STOP);
    p->triangle[i] = at.triangle;
    p->texel[i] = mtx_walker_texel_at(s.corner_uvs, &at, k->width, k->height, &p->x[i], &p->y[i]);
  }
}

/* What species `species` reads at the end of sensor trace i of `probes`. */
MTX_FN float mtx_sense(MTX_TABLES s, MTX_GLOBAL const float* pheromone,
                       MTX_GLOBAL const float* field, const mtx_momas_probes* probes, int probe,
                       mtx_u32 species, const mtx_momas_constants* k) {
  const mtx_u32 texel = probes->texel[probe];
  int rx = MTX_CAST(int, k->sensor_size), ry = rx;
  if (rx == 0 && k->surface_mode)
    return mtx_sense_footprint_at(s, pheromone, field, probes->triangle[probe], probes->x[probe], probes->y[probe],
                                  texel, species, k);
  if (rx == 0) return mtx_sensed_value(pheromone, field, texel, species, k);
  if (k->surface_mode) {
    /* The square's reach is in surface units: r length units along each texel axis. */
    MTX_GLOBAL const float* tpu = s.texels_per_unit + 2 * probes->triangle[probe];
    const float fx = MTX_CAST(float, rx) * k->length_unit * tpu[0] + 0.5f;
    const float fy = MTX_CAST(float, ry) * k->length_unit * tpu[1] + 0.5f;
    rx = fx < MTX_MAX_FOOTPRINT_TEXELS ? MTX_CAST(int, fx) : MTX_MAX_FOOTPRINT_TEXELS;
    ry = fy < MTX_MAX_FOOTPRINT_TEXELS ? MTX_CAST(int, fy) : MTX_MAX_FOOTPRINT_TEXELS;
  }
  /* MoMaS' square kernel: the sum over the (2r+1)^2 texels around the sensor texel,
   * clamped to the texture (texels outside every island hold 0). */
  const int cx = MTX_CAST(int, texel % k->width), cy = MTX_CAST(int, texel / k->width);
  const int w = MTX_CAST(int, k->width), h = MTX_CAST(int, k->height);
  const int x0 = cx - rx < 0 ? 0 : cx - rx, x1 = cx + rx >= w ? w - 1 : cx + rx;
  const int y0 = cy - ry < 0 ? 0 : cy - ry, y1 = cy + ry >= h ? h - 1 : cy + ry;
  float v = 0.0f;
  for (int y = y0; y <= y1; ++y)
    for (int x = x0; x <= x1; ++x)
      v += mtx_sensed_value(pheromone, field, MTX_CAST(mtx_u32, y * w + x), species, k);
  return v;
}

/* The texels that the box [x - ex, x + ex] x [y - ey, y + ey] (in texels) overlaps,
 * clipped to the texture, and its area on island texels of the footprint's island. */
MTX_FN float mtx_footprint_cover(MTX_TABLES s, const mtx_momas_constants* k, float x,
                                 float y, float ex, float ey, mtx_footprint* box) {
  box->x0 = mtx_floor_int(x - ex);
  box->x1 = mtx_ceil_int(x + ex) - 1;
  box->y0 = mtx_floor_int(y - ey);
  box->y1 = mtx_ceil_int(y + ey) - 1;
  mtx_clip_footprint(box, k);
  float covered = 0.0f;
  for (int iy = box->y0; iy <= box->y1; ++iy) {
    const float oy = mtx_min(y + ey, MTX_CAST(float, iy + 1)) - mtx_max(y - ey, MTX_CAST(float, iy));
    if (!(oy > 0.0f)) continue;
    for (int ix = box->x0; ix <= box->x1; ++ix) {
      const float ox = mtx_min(x + ex, MTX_CAST(float, ix + 1)) - mtx_max(x - ex, MTX_CAST(float, ix));
      const mtx_u32 i = MTX_CAST(mtx_u32, iy) * k->width + MTX_CAST(mtx_u32, ix);
      if (ox > 0.0f && mtx_in_footprint(s, i, box)) covered += ox * oy;
    }
  }
  return covered;
}

/* Surface units, a footprint much narrower than a texel along an axis (texels over two
 * length units long: strongly stretched UVs, a texture much coarser than the pattern
 * scale). A texel is marked when the footprint covers its sample point: along such an
 * axis a random point of the texel, fixed by (seed, texel) alone, so the same for every
 * agent, step, thread and backend; along the other axis its centre, as for small
 * texels. Texels are then marked in proportion to the share of them the footprints
 * cover: a trail across a wide texel no longer marks all of it, which painted trails
 * as wide as the texels (streaks along the stretch). The points are fixed rather than
 * drawn anew every step, which made the pattern depend on the time step (cells 1.3x
 * longer at 1/120 s than at 1/240 s on a torus with 2.2-unit texels). jx, jy: the axes
 * sampled (ex, ey may have grown past their first size where the footprint lay partly
 * off its island, as in mtx_mark_footprint). Texels of the footprint's island only,
 * free of obstacles. */
MTX_FN void mtx_mark_sampled(MTX_TABLES s, MTX_GLOBAL const float* field,
                             MTX_GLOBAL mtx_u8* own_marks, float x, float y, float ex, float ey,
                             int jx, int jy, mtx_u32 island, const mtx_momas_constants* k) {
  /* Texels whose sample point may lie within the footprint: every texel it overlaps along
   * a sampled axis, those whose centres it holds along the other. */
  mtx_footprint box;
  mtx_centres_within(x, y, ex, ey, k, &box);
  if (jx) {
    box.x0 = mtx_floor_int(x - ex);
    box.x1 = mtx_floor_int(x + ex);
  }
  if (jy) {
    box.y0 = mtx_floor_int(y - ey);
    box.y1 = mtx_floor_int(y + ey);
  }
  mtx_clip_footprint(&box, k);
  const mtx_u64 key = mtx_rng_init(k->seed, MTX_RNG_DEPOSIT, 0, 0);
  for (int iy = box.y0; iy <= box.y1; ++iy)
    for (int ix = box.x0; ix <= box.x1; ++ix) {
      const mtx_u32 i = MTX_CAST(mtx_u32, iy) * k->width + MTX_CAST(mtx_u32, ix);
      if (s.texel_island[i] != MTX_CAST(int, island)) continue;
      const mtx_u64 h = mtx_mix64(key ^ MTX_CAST(mtx_u64, i));
      const float sx = MTX_CAST(float, ix) + (jx ? MTX_CAST(float, h >> 40) * (1.0f / 16777216.0f) : 0.5f);
      const float sy = MTX_CAST(float, iy) + (jy ? MTX_CAST(float, (h >> 16) & 0xffffffUL) * (1.0f / 16777216.0f) : 0.5f);
      if (fabs(x - sx) <= ex && fabs(y - sy) <= ey && !mtx_is_obstacle(field, i, k)) MTX_MARK(own_marks, i);
    }
}

/* Surface units: marks the texel under walker w if it is an island texel, and every
 * texel of the walker's UV island, free of obstacles, whose centre lies within half a
 * length unit of the walker along each texel axis (the footprint has the same 3D size
 * wherever texels are small or large; at most MTX_MAX_FOOTPRINT_TEXELS each side). Where
 * part of that box lies off the island (gutter between islands or between the teeth of a
 * UV pole's fan, which are narrower than a texel near the pole; across a seam; off an
 * open boundary) the box grows until its area on island texels is one square unit, so a
 * deposit covers the same surface there as anywhere. The texel under the walker need not
 * be an island texel (next to a pole it seldom is). Along an axis where texels are over
 * two units long, marks are sampled instead (mtx_mark_sampled). Marks depend only on
 * where the walker is, so a trail is the union of its footprints at any
 * substep density. (x, y): the walker's point in texels (mtx_walker_texel_at), over
 * `texel`. */
MTX_FN void mtx_mark_footprint(MTX_TABLES s, MTX_GLOBAL const float* field,
                               MTX_GLOBAL mtx_u8* own_marks, const mtx_walker* w,
                               mtx_u32 texel, float x, float y, const mtx_momas_constants* k) {
  MTX_GLOBAL const float* tpu = s.texels_per_unit + 2 * w->triangle;
  const float limit = MTX_CAST(float, MTX_MAX_FOOTPRINT_TEXELS);
  float ex = mtx_min(0.5f * k->length_unit * tpu[0], limit);
  float ey = mtx_min(0.5f * k->length_unit * tpu[1], limit);
  /* Where a texel is over twice as long as the footprint along one axis and over twice
   * as long along it as along the other (strong UV stretch), marks are sampled along it
   * (mtx_mark_sampled). Other texels keep the rule below, which over-marks a long axis:
   * a texture coarser than the pattern scale (texels large both ways) blurs trails
   * evenly, without streaks. Sampling from 1 unit on was tried: an open cylinder's
   * boundary band (texels 1.4 units around) fell from 0.95 to 0.74 of the mean; and in
   * texels large both ways: a preset's coverage at 128^2 rose from 0.36-0.43 to 0.58. */
  const int jx = ex < 0.25f && ex < 0.5f * ey, jy = ey < 0.25f && ey < 0.5f * ex;
  if (!(jx | jy)) {
    if (s.classes[texel] == MTX_TEXEL_INSIDE) MTX_MARK(own_marks, texel);
    if (ex < 0.5f && ey < 0.5f) return; /* the footprint lies within that texel */
  }
  mtx_footprint box;
  box.island = s.island[w->triangle];
  /* The common case: every texel the box overlaps is a texel of the walker's island, so
   * it covers its whole area (the test below would find the same within rounding, far
   * under its 0.1% margin) and every texel whose centre it holds is marked. */
  if (!(jx | jy)) mtx_centres_within(x, y, ex, ey, k, &box);
  /* The texels the box overlaps lie within one texel around those whose centres it holds
   * (where it holds some along both axes), so that wider box is checked. */
  if (!(jx | jy) && box.x0 <= box.x1 && box.y0 <= box.y1 &&
      mtx_box_within_island(s, texel, box.x0 - 1, box.x1 + 1, box.y0 - 1, box.y1 + 1, box.island, k)) {
    /* Held apart: each mark (an atomic store) would make the compiler load them anew. */
    const mtx_u32 width = k->width;
    const int fields = MTX_FIELDS && k->has_fields;
    for (int iy = box.y0; iy <= box.y1; ++iy)
      for (int ix = box.x0; ix <= box.x1; ++ix) {
        const mtx_u32 i = MTX_CAST(mtx_u32, iy) * width + MTX_CAST(mtx_u32, ix);
        if (!fields || !(field[i] < MTX_OBSTACLE_THRESHOLD)) MTX_MARK(own_marks, i);
      }
    return;
  }
  const float target = 4.0f * ex * ey;
  float covered = mtx_footprint_cover(s, k, x, y, ex, ey, &box);
  for (int grow = 0; grow < 3 && covered < 0.999f * target && ex < limit && ey < limit; ++grow) {
    const float f = covered > 0.0f ? mtx_min(2.0f, sqrt(target / covered)) : 2.0f;
    ex = mtx_min(ex * f, limit);
    ey = mtx_min(ey * f, limit);
    covered = mtx_footprint_cover(s, k, x, y, ex, ey, &box);
  }
  if (jx | jy) {
    mtx_mark_sampled(s, field, own_marks, x, y, ex, ey, jx, jy, box.island, k);
    return;
  }
  mtx_footprint centres;
  mtx_centres_within(x, y, ex, ey, k, &centres);
  for (int iy = centres.y0; iy <= centres.y1; ++iy)
    for (int ix = centres.x0; ix <= centres.x1; ++ix) {
      const mtx_u32 i = MTX_CAST(mtx_u32, iy) * k->width + MTX_CAST(mtx_u32, ix);
      if (mtx_in_footprint(s, i, &box) && !mtx_is_obstacle(field, i, k)) MTX_MARK(own_marks, i);
    }
}

/* Food with hunger (plasmodial-slime-readme.md, "Food Sources"), after the MoMaS turn:
 * finds the nearest source with food left; within food_radius the agent eats (hunger 0,
 * the source's eater counter + 1), otherwise a hungry agent blends its heading toward
 * the source, projected into its triangle, with weight min(1, hunger^8 strength / d^2). */
MTX_FN void mtx_food_steer(MTX_TABLES s, mtx_walker* w, float* hunger,
                           const mtx_momas_constants* k) {
  MTX_GLOBAL const mtx_frame* f = s.frames + w->triangle;
  MTX_GLOBAL const float* g = s.frame3d + 9 * w->triangle;
  const float lx = w->bary[1] * f->a + w->bary[2] * f->bx, ly = w->bary[2] * f->by;
  const float px = g[0] + lx * g[3] + ly * g[6];
  const float py = g[1] + lx * g[4] + ly * g[7];
  const float pz = g[2] + lx * g[5] + ly * g[8];
  mtx_u32 best = 0;
  float best_d2 = 0.0f;
  for (mtx_u32 j = 0; j < k->food_count; ++j) {
    const float dx = s.food[4 * j] - px, dy = s.food[4 * j + 1] - py, dz = s.food[4 * j + 2] - pz;
    const float d2 = dx * dx + dy * dy + dz * dz;
    if (j == 0 || d2 < best_d2) {
      best = j;
      best_d2 = d2;
    }
  }
  if (best_d2 <= k->food_radius * k->food_radius) {
    *hunger = 0.0f;
    MTX_COUNT(s.eaters, best);
    return;
  }
  if (!(*hunger > 0.0f)) return;
  const float dx = s.food[4 * best] - px, dy = s.food[4 * best + 1] - py,
              dz = s.food[4 * best + 2] - pz;
  mtx_vec2 toward;
  toward.x = dx * g[3] + dy * g[4] + dz * g[5];
  toward.y = dx * g[6] + dy * g[7] + dz * g[8];
  if (!(toward.x * toward.x + toward.y * toward.y > 0.0f)) return; /* straight above/below */
  toward = mtx_unit(toward);
  /* Plasmodial Slime's blend weight |F| (1 - fullness)^8 = |F| hunger^8, clamped: the
   * pull is felt only when quite hungry. Heading vectors are blended, not angles, so no
   * jump where angles wrap around. */
  const float h2 = *hunger * *hunger, h4 = h2 * h2;
  const float weight = mtx_min(1.0f, h4 * h4 * s.food[4 * best + 3] / best_d2);
  mtx_vec2 h;
  h.x = (1.0f - weight) * w->heading.x + weight * toward.x;
  h.y = (1.0f - weight) * w->heading.y + weight * toward.y;
  if (h.x * h.x + h.y * h.y > 0.0f) w->heading = mtx_unit(h);
}

/* One decision of walker w (of species `species`) and the move after it, given its
 * probes (mtx_momas_probe): sense, turn, then move k->move_length in k->substeps pieces,
 * marking deposits. `rng` is the step's random state (mtx_momas_agent_finish); `first`:
 * the step's first decision, where hunger grows. */
MTX_FN void mtx_momas_decision(MTX_TABLES s, MTX_GLOBAL const float* pheromone,
                               MTX_GLOBAL const float* field, MTX_GLOBAL mtx_u8* marks,
                               mtx_walker* w, float* hunger, mtx_u32 species,
                               const mtx_momas_constants* k, const mtx_momas_probes* probes,
                               mtx_u64* rng, int first) {
  /* One texel each (MoMaS' own sensor, the common case) is read here directly: the
   * general reading is a call each. */
  const int one_texel = k->sensor_size == 0u && !k->surface_mode;
  float left = 0.0f, front = 1.0f, right = 0.0f; /* no sensing this step: straight on */
  if (!k->coast) {
    left = one_texel ? mtx_sensed_value(pheromone, field, probes->texel[0], species, k)
                     : mtx_sense(s, pheromone, field, probes, 0, species, k);
    front = one_texel ? mtx_sensed_value(pheromone, field, probes->texel[1], species, k)
                      : mtx_sense(s, pheromone, field, probes, 1, species, k);
    right = one_texel ? mtx_sensed_value(pheromone, field, probes->texel[2], species, k)
                      : mtx_sense(s, pheromone, field, probes, 2, species, k);
  }

  /* Steering: keep going only while the front is strictly strongest, else turn toward
   * the stronger side, or to a random side on a tie (so agents on bare ground wander
   * instead of running straight). The turn is scaled by r ~ U[0,1), the paper's jitter. */
  const float r = mtx_rng_float(rng);
  if (!(front > left && front > right)) {
    float side;
    if (left > right)
      side = 1.0f;
    else if (right > left)
      side = -1.0f;
    else
      side = mtx_rng_float(rng) < 0.5f ? 1.0f : -1.0f;
    /* Surface units: mean r = 1/2 as MoMaS, the spread around it time-step independent. */
    const float amount = k->surface_mode ? 0.5f + (r - 0.5f) * k->turn_jitter : r;
    const float turn = side * amount * k->max_turn[species];
    float c, s_;
    mtx_cos_sin(turn, &c, &s_);
    w->heading = mtx_renormalised(mtx_rotate(w->heading, c, s_));
  }
  /* Hunger grows once a step (hunger_step is per step); eating and the pull toward food
   * come with each decision, as the turn does: per MoMaS tick in surface units, so an
   * agent at a source eats 60 units a simulated second at any time step. */
  if (MTX_FOOD && k->hunger_step > 0.0f) {
    if (first) *hunger = mtx_min(1.0f, *hunger + k->hunger_step);
    if (k->food_count > 0 && !k->coast) mtx_food_steer(s, w, hunger, k);
  }

  /* Move in equal substeps, leaving a deposit after each: a line-integrated trail whose
   * total length does not depend on the substep count. A substep that would carry the
   * agent from free ground into an obstacle is undone and the agent turns back, so no
   * agent ever stands in an obstacle it did not start in. At an open boundary the agent
   * scatters (the cosine law, drawing on its steering numbers): with a mirror bounce a
   * trail along the wall kept every agent that drifted against it, and open boundaries
   * held 1.8-1.9x the interior's pheromone. */
  const float move_length = k->move_length[species];
  const float sub_length = move_length / MTX_CAST(float, k->substeps);
  MTX_GLOBAL mtx_u8* own_marks = marks + species * mtx_texel_count(k);
  mtx_u32 texel = probes->here;
  /* Usually the whole move stays inside the agent's triangle: no edge tests then. */
  const int inside = mtx_walk_stays_inside(probes->clearance, move_length);
  for (mtx_u32 i = 0; i < k->substeps; ++i) {
    const mtx_walker before = *w;
    const mtx_u32 before_texel = texel;
    if (inside)
      mtx_walk_inside_known(s.frames, w, sub_length);
    else
      mtx_walk_until(s.frames, s.adjacency, w, sub_length, 0, 0, MTX_BOUNDARY_SCATTER, rng);
    float x = 0.0f, y = 0.0f; /* surface units: the point in texels, for its footprint */
    texel = k->surface_mode ? mtx_walker_texel_at(s.corner_uvs, w, k->width, k->height, &x, &y)
                            : mtx_walker_texel(s.corner_uvs, w, k->width, k->height);
    if (mtx_is_obstacle(field, texel, k)) {
      if (!mtx_is_obstacle(field, before_texel, k)) {
        *w = before;
        w->heading.x = -w->heading.x;
        w->heading.y = -w->heading.y;
        texel = before_texel;
      }
      continue; /* nothing is deposited in an obstacle */
    }
    if (k->surface_mode) {
      mtx_mark_footprint(s, field, own_marks, w, texel, x, y, k);
      continue;
    }
    /* Marked whatever its class: applying the marks keeps those of island texels only
     * (apply_deposits), a pass in texel order instead of a scattered read here. */
    MTX_MARK(own_marks, texel);
  }
}

/* The rest of one step of walker w (agent number `agent`, of species `species`), given
 * its probes (mtx_momas_probe). `pheromone` holds species_count planes of width * height
 * texels, `marks` as many byte planes; `field` is the static field plane (read only when
 * k->has_fields); `hunger` is the agent's hunger, changed only while k->hunger_step > 0.
 * Usually one decision; k->decisions of them (a step over 1/60 s in surface units: one
 * per MoMaS tick), each after probes taken where the last move ended. */
MTX_FN void mtx_momas_agent_finish(MTX_TABLES s, MTX_GLOBAL const float* pheromone,
                                   MTX_GLOBAL const float* field, MTX_GLOBAL mtx_u8* marks,
                                   mtx_walker* w, float* hunger, mtx_u32 species, mtx_u64 agent,
                                   const mtx_momas_constants* k, const mtx_momas_probes* probes) {
  mtx_u64 rng = mtx_rng_init_step(k->steer_key, agent, k->step); /* key: mtx_rng_key(seed, MTX_RNG_STEER) */
  const mtx_u32 decisions = k->decisions > 1u ? k->decisions : 1u;
  mtx_momas_decision(s, pheromone, field, marks, w, hunger, species, k, probes, &rng, 1);
  for (mtx_u32 i = 1; i < decisions; ++i) {
    mtx_momas_probes again;
    mtx_momas_probe(s, w, species, k, &again);
    mtx_momas_decision(s, pheromone, field, marks, w, hunger, species, k, &again, &rng, 0);
  }
}

/* Updates walker w (agent number `agent`, of species `species`) by one step: its probes,
 * then the rest (mtx_momas_agent_finish). */
MTX_FN void mtx_momas_agent_step(MTX_TABLES s, MTX_GLOBAL const float* pheromone,
                                 MTX_GLOBAL const float* field, MTX_GLOBAL mtx_u8* marks,
                                 mtx_walker* w, float* hunger, mtx_u32 species, mtx_u64 agent,
                                 const mtx_momas_constants* k) {
  mtx_momas_probes probes;
  mtx_momas_probe(s, w, species, k, &probes);
  mtx_momas_agent_finish(s, pheromone, field, marks, w, hunger, species, agent, k, &probes);
}

MTX_END_NAMESPACE

#endif
