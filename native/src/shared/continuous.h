/* continuous.h — the continuous slime model (layton-intrinsic-slime.md §3.2) for one
 * agent and one step: turnover (exposure against an exponential threshold, respawn at an
 * area-uniform point), turn decisions at a fixed frequency (omega / f_i applied as one
 * impulse every 1 / f_i seconds, timed per agent), a move of v * dt, and r_dep * dt
 * deposited evenly along the path walked (Eq. 4). Reads the concentration; deposits are
 * fixed-point integer sums, so the order of writers cannot change the result. */
#ifndef MOLDTEX_SHARED_CONTINUOUS_H
#define MOLDTEX_SHARED_CONTINUOUS_H

#ifndef __OPENCL_C_VERSION__
#include "shared/constants.h"
#include "shared/momas.h"
#include "shared/portable.h"
#include "shared/rng.h"
#include "shared/texel_sampling.h"
#include "shared/walk.h"
#endif

MTX_BEGIN_NAMESPACE

#define MTX_RNG_TURNOVER 5
#define MTX_RNG_DECIDE 6
/* At most this many turn decisions in one step (a time step much longer than 1 / f_i
 * aliases anyway: the paper's limit). */
#define MTX_MAX_DECISIONS_PER_STEP 16
/* A move is split into pieces no longer than max_piece texels (a deposit every piece), but
 * into no more than this many. */
#define MTX_MAX_DEPOSIT_PIECES 64

/* Parameter maps the agents read (layton-intrinsic-slime.md §3.3): per texel multipliers
 * of a parameter, looked up at the agent's texel; the order of moldtex_map's first
 * values. A plane index of -1 means no map (a multiplier of 1). */
#define MTX_MAP_MOVE 0
#define MTX_MAP_TURN 1
#define MTX_MAP_SENSOR_DISTANCE 2
#define MTX_MAP_SENSOR_ANGLE 3
#define MTX_MAP_DEPOSIT 4
#define MTX_MAP_LIFETIME 5
#define MTX_MAP_ACTIVATION 6
#define MTX_MAP_SPAWN 7
#define MTX_AGENT_MAPS 8
/* A respawn under a spawn map draws a triangle by area times its sampled weight, then
 * points in it until one is accepted against the triangle's largest weight. */
#define MTX_MAX_SPAWN_TRIES 64
#define MTX_SPAWN_TRIES_PER_TRIANGLE 16

/* Per-step constants of the continuous model, derived on the host. 64-bit fields first
 * so C++ and OpenCL C agree on the layout. */
typedef struct mtx_continuous_constants {
  mtx_u64 seed;
  mtx_u64 step;
  mtx_u64 turnover_key, decide_key; /* mtx_rng_key(seed, MTX_RNG_TURNOVER / MTX_RNG_DECIDE) */
  /* attraction[4 * s + k]: weight of species k's concentration in species s's sensing. */
  float attraction[MTX_MAX_SPECIES * MTX_MAX_SPECIES];
  /* Per species plane: 1 / U, so sensing compares concentrations relative to the uniform
   * steady state and static fields (attractors) keep their meaning at any deposit rate. */
  float sense_scale[MTX_MAX_SPECIES];
  float move_length;     /* v * dt */
  float sensor_length;   /* d */
  float sensor_cos, sensor_sin;
  float turn_impulse;    /* omega / f_i, radians */
  float decision_period; /* 1 / f_i */
  float dt;
  float exposure_step;   /* dt / tau; 0 = no turnover */
  float activation_time; /* t_a */
  float max_piece;       /* longest deposit piece in texel units (1) */
  mtx_u32 width, height;
  mtx_u32 species_count;
  mtx_u32 has_fields;
  mtx_u32 triangle_count; /* entries of the alias table */
  mtx_u32 deposit_on;     /* 0 when r_dep = 0 (nothing to add) */
  mtx_i32 deposit_units;  /* fixed-point units of one agent's deposit in one step */
  mtx_u32 bias_on;        /* a bias field is set and bias_rate > 0 */
  float bias_rate;        /* bias_strength, per second */
  mtx_u32 bias_symmetry;  /* n copies of the bias direction */
  mtx_u32 bias_spawn;     /* respawns face a bias direction (needs a bias field) */
  mtx_u32 maps_on;        /* some plane of map_plane is >= 0 */
  mtx_i32 map_plane[MTX_AGENT_MAPS]; /* plane of each agent map in `maps`, -1 = none */
  mtx_u32 absorb;         /* agents that meet an open boundary die there (Fig. 18) */
  /* Cells per plane of the concentration agents read and of their deposit sums: the
   * texels (width * height), or on the intrinsic domain its lattice's nodes. */
  mtx_u32 plane_cells;
  /* 1: the deposit sums each agent is given are its thread's own (plain adds; CPU only),
   * 0: shared by all (atomic adds). */
  mtx_u32 exclusive_sums;
} mtx_continuous_constants;

/* The per-agent clocks of the continuous model. */
typedef struct mtx_agent_life {
  float clock;     /* seconds since the last turn decision */
  float age;       /* seconds since the last (re)spawn */
  float exposure;  /* lambda: accumulated dt / tau */
  float threshold; /* lambda_t = -ln X, drawn once per lifetime */
} mtx_agent_life;

/* Area-uniform point with a uniform heading: a triangle from the alias table (Vose: one
 * uniform picks a column, a second keeps it or takes its alias), then uniform
 * barycentrics. */
MTX_FN void mtx_respawn(MTX_GLOBAL const float* alias_prob, MTX_GLOBAL const mtx_u32* alias_index,
                        mtx_u32 triangle_count, mtx_walker* w, mtx_u64* rng) {
  const float r0 = mtx_rng_float(rng) * MTX_CAST(float, triangle_count);
  mtx_u32 column = MTX_CAST(mtx_u32, r0);
  column = column >= triangle_count ? triangle_count - 1 : column;
  const mtx_u32 t = mtx_rng_float(rng) < alias_prob[column] ? column : alias_index[column];
  const float a = sqrt(mtx_rng_float(rng)), b = mtx_rng_float(rng);
  w->triangle = t;
  w->bary[0] = 1.0f - a;
  w->bary[1] = a * (1.0f - b);
  w->bary[2] = a * b;
  const float angle = 6.28318530718f * mtx_rng_float(rng);
  w->heading.x = cos(angle);
  w->heading.y = sin(angle);
}

/* The multiplier of agent map `which` at texel `texel` (1 without that map). */
MTX_FN float mtx_map_value(MTX_GLOBAL const float* maps, const mtx_continuous_constants* k, int which,
                           mtx_u32 texel) {
  const mtx_i32 plane = k->map_plane[which];
  return plane < 0 ? 1.0f : maps[MTX_CAST(mtx_u64, plane) * (k->width * k->height) + texel];
}

/* A respawn under a spawn map: the alias table weighs triangles by area times their mean
 * spawn weight; within the drawn triangle a point is kept with probability weight / the
 * triangle's largest weight (spawn_max), else another point of the same triangle is
 * drawn; after MTX_SPAWN_TRIES_PER_TRIANGLE misses (a triangle the map's edge barely
 * enters) another triangle is drawn, and after MTX_MAX_SPAWN_TRIES the point of highest
 * weight drawn is kept. */
MTX_FN void mtx_respawn_weighted(MTX_TABLES s, MTX_GLOBAL const float* alias_prob,
                                 MTX_GLOBAL const mtx_u32* alias_index, MTX_GLOBAL const float* maps,
                                 MTX_GLOBAL const float* spawn_max, const mtx_continuous_constants* k,
                                 mtx_walker* w, mtx_u64* rng) {
  mtx_respawn(alias_prob, alias_index, k->triangle_count, w, rng);
  if (k->map_plane[MTX_MAP_SPAWN] < 0) return;
  float best_weight = -1.0f;
  float best[3] = {w->bary[0], w->bary[1], w->bary[2]};
  mtx_u32 best_triangle = w->triangle;
  for (int tries = 0; tries < MTX_MAX_SPAWN_TRIES; ++tries) {
    /* Every MTX_SPAWN_TRIES_PER_TRIANGLE misses, another triangle (one the map's edge
     * barely enters may hold little weight). */
    if (tries > 0 && tries % MTX_SPAWN_TRIES_PER_TRIANGLE == 0) {
      const mtx_vec2 heading = w->heading;
      mtx_respawn(alias_prob, alias_index, k->triangle_count, w, rng);
      w->heading = heading;
    } else if (tries > 0) {
      const float a = sqrt(mtx_rng_float(rng)), b = mtx_rng_float(rng);
      w->bary[0] = 1.0f - a;
      w->bary[1] = a * (1.0f - b);
      w->bary[2] = a * b;
    }
    const float top = spawn_max[w->triangle];
    if (!(top > 0.0f)) return;
    const float here = mtx_map_value(maps, k, MTX_MAP_SPAWN, mtx_point_cell(s, w, k->width, k->height));
    if (mtx_rng_float(rng) * top <= here) return;
    if (here > best_weight) {
      best_weight = here;
      best_triangle = w->triangle;
      for (int c = 0; c < 3; ++c) best[c] = w->bary[c];
    }
  }
  w->triangle = best_triangle;
  for (int c = 0; c < 3; ++c) w->bary[c] = best[c];
}

/* -ln X for X uniform in (0, 1]. */
MTX_FN float mtx_exponential(mtx_u64* rng) { return -log(1.0f - mtx_rng_float(rng)); }

/* What species `species` senses over a reading stencil (mtx_texel_stencil_of with
 * reading = 1): its attraction-weighted sum of every species' concentration relative to
 * U, plus the static field, bilinear over the island's cells. An obstacle anywhere in the
 * stencil reads as the obstacle. */
MTX_FN float mtx_continuous_read(MTX_GLOBAL const float* u, MTX_GLOBAL const float* field,
                                 const mtx_texel_stencil* st, mtx_u32 species,
                                 const mtx_continuous_constants* k) {
  if (st->count == 0) return 0.0f;
  const mtx_u32 texels = k->plane_cells;
  float v = 0.0f;
  for (int c = 0; c < 4; ++c) {
    if (!(st->weight[c] > 0.0f)) continue;
    float here = 0.0f;
    for (mtx_u32 q = 0; q < MTX_SPECIES_COUNT(k); ++q)
      here += k->attraction[MTX_MAX_SPECIES * species + q] * k->sense_scale[q] * u[q * texels + st->cell[c]];
    if (MTX_FIELDS && k->has_fields) {
      const float f = field[st->cell[c]];
      if (f < MTX_OBSTACLE_THRESHOLD) return f;
      here += f;
    }
    v += st->weight[c] * here;
  }
  return v;
}

/* The three sensor traces (left, front, right) of walker `from` as they start: at its
 * point, the sides turned by (c, +-sn). */
MTX_FN void mtx_continuous_trace_starts(const mtx_walker* from, float c, float sn, mtx_walker* at) {
  for (int i = 0; i < 3; ++i) {
    at[i] = *from;
    /* (The front turned by (1, 0) too, as it always was: that keeps the sign of a zero.) */
    at[i].heading = i == 1 ? mtx_rotate(from->heading, 1.0f, 0.0f) : mtx_rotate(from->heading, c, i == 0 ? sn : -sn);
  }
}

/* The ends of the three sensor traces (left, front, right) of `length` from walker
 * `from`, the sides turned by (c, +-sn): where the traces end (triangle and weights;
 * their headings are not used). Located through the unfolded neighbours where the
 * tables have them (mtx_trace_unfolded), walked where not (open boundaries bounce). */
MTX_FN void mtx_continuous_traces(MTX_TABLES s, const mtx_walker* from, float c, float sn,
                                  float length, mtx_walker* at) {
  mtx_continuous_trace_starts(from, c, sn, at);
  for (int i = 0; i < 3; ++i)
    if (mtx_walk_trace(s.frames, s.adjacency, s.unfolded, &at[i], length, MTX_BOUNDARY_BOUNCE))
      mtx_clamp_bary(at[i].bary); /* on the simplex, as a walk leaves its weights */
}

/* The reading stencils of the three sensors (left, front, right) of walker `from`. */
MTX_FN void mtx_continuous_probes(MTX_TABLES s, const mtx_walker* from, float c, float sn,
                                  float length, const mtx_continuous_constants* k, mtx_texel_stencil* st) {
  mtx_walker at[3];
  mtx_continuous_traces(s, from, c, sn, length, at);
  for (int i = 0; i < 3; ++i) mtx_texel_stencil_of(s, &at[i], k->width, k->height, 1, &st[i]);
}

/* What an agent carries from the first part of its step (mtx_continuous_agent_begin) to
 * the rest (mtx_continuous_agent_finish): its parameters where it stands (the maps
 * applied), its age at the start of the step, and whether it decides this step; if so,
 * where its first decision's three sensor traces end (left, front, right) and, once
 * mtx_continuous_plan_stencils has run, their reading stencils. */
typedef struct mtx_continuous_plan {
  float move_length, sensor_length, sensor_cos, sensor_sin, turn_impulse, activation_time;
  float born;
  mtx_i32 deposit_units;
  int decide;
  mtx_walker at[3];
  mtx_texel_stencil probe[3];
} mtx_continuous_plan;

/* The first part of one step of agent `agent` (walker w, clocks life): turnover, the
 * parameter maps where it then stands and its decision clock. Where it decides, the
 * first decision's sensor traces follow (mtx_continuous_traces into plan->at, or a
 * backend's own batch of traces). Reads no concentration, so a backend can run it for a
 * batch of agents and fetch the cells their sensors read together. */
MTX_FN void mtx_continuous_agent_begin(MTX_TABLES s, MTX_GLOBAL const float* alias_prob,
                                       MTX_GLOBAL const mtx_u32* alias_index,
                                       MTX_GLOBAL const float* bias, MTX_GLOBAL const float* maps,
                                       MTX_GLOBAL const float* spawn_max, mtx_walker* w,
                                       mtx_agent_life* life, mtx_u64 agent,
                                       const mtx_continuous_constants* k, mtx_continuous_plan* plan) {
  /* Turnover (§3.2): exposure grows by dt / tau; past the threshold the agent decays and
   * a new one starts at a uniform point of the surface (or one drawn by the spawn map),
   * age 0, a fresh threshold. A lifetime map scales tau where the agent is (§3.3); where
   * it is 0 the agent decays at once (a sink), even without turnover elsewhere. */
  float exposure_step = k->exposure_step;
  int sink = 0;
  if (k->maps_on && k->map_plane[MTX_MAP_LIFETIME] >= 0) {
    const float m = mtx_map_value(maps, k, MTX_MAP_LIFETIME, mtx_point_cell(s, w, k->width, k->height));
    if (m > 0.0f)
      exposure_step /= m;
    else
      sink = 1;
  }
  /* (An agent absorbed by a boundary last step has its threshold at 0.) */
  if (exposure_step > 0.0f || sink || life->exposure >= life->threshold) {
    life->exposure += exposure_step;
    if (sink || life->exposure >= life->threshold) {
      mtx_u64 rng = mtx_rng_init_keyed(k->turnover_key, agent, k->step);
      mtx_respawn_weighted(s, alias_prob, alias_index, maps, spawn_max, k, w, &rng);
      if (k->bias_spawn) { /* face one of the n bias directions, chosen at random */
        MTX_GLOBAL const float* b = bias + 2 * w->triangle;
        const float length = sqrt(b[0] * b[0] + b[1] * b[1]);
        if (length > 0.0f) {
          const mtx_u32 copy = MTX_CAST(mtx_u32, mtx_rng_float(&rng) * MTX_CAST(float, k->bias_symmetry));
          const float angle = 6.28318530718f * MTX_CAST(float, copy) / MTX_CAST(float, k->bias_symmetry);
          mtx_vec2 h;
          h.x = b[0] / length;
          h.y = b[1] / length;
          w->heading = mtx_unit(mtx_rotate(h, cos(angle), sin(angle)));
        }
      }
      life->exposure = 0.0f;
      life->threshold = mtx_exponential(&rng);
      life->age = 0.0f;
      life->clock = k->decision_period * mtx_rng_float(&rng);
    }
  }
  plan->born = life->age; /* age at the start of this step */
  life->age += k->dt;

  /* The other parameter maps, where the agent is now (§3.3). */
  float move_length = k->move_length, sensor_length = k->sensor_length;
  float sensor_cos = k->sensor_cos, sensor_sin = k->sensor_sin, turn_impulse = k->turn_impulse;
  float activation_time = k->activation_time;
  mtx_i32 deposit_units = k->deposit_units;
  if (k->maps_on) {
    const mtx_u32 texel = mtx_point_cell(s, w, k->width, k->height);
    move_length *= mtx_map_value(maps, k, MTX_MAP_MOVE, texel);
    sensor_length *= mtx_map_value(maps, k, MTX_MAP_SENSOR_DISTANCE, texel);
    turn_impulse *= mtx_map_value(maps, k, MTX_MAP_TURN, texel);
    activation_time *= mtx_map_value(maps, k, MTX_MAP_ACTIVATION, texel);
    if (k->map_plane[MTX_MAP_SENSOR_ANGLE] >= 0) {
      const float angle = atan2(k->sensor_sin, k->sensor_cos) * mtx_map_value(maps, k, MTX_MAP_SENSOR_ANGLE, texel);
      sensor_cos = cos(angle);
      sensor_sin = sin(angle);
    }
    /* deposit_units leaves room for the map's largest value (continuous_rules.cpp). */
    if (k->map_plane[MTX_MAP_DEPOSIT] >= 0)
      deposit_units = MTX_CAST(mtx_i32, MTX_CAST(float, deposit_units) * mtx_map_value(maps, k, MTX_MAP_DEPOSIT, texel) + 0.5f);
  }

  plan->move_length = move_length;
  plan->sensor_length = sensor_length;
  plan->sensor_cos = sensor_cos;
  plan->sensor_sin = sensor_sin;
  plan->turn_impulse = turn_impulse;
  plan->activation_time = activation_time;
  plan->deposit_units = deposit_units;
  life->clock += k->dt;
  plan->decide = life->clock >= k->decision_period;
}

/* The second part (after the traces): the reading stencils where the plan's sensor
 * traces end. Apart from the first, so a backend can fetch what locating them reads for
 * a batch of agents. */
MTX_FN void mtx_continuous_plan_stencils(MTX_TABLES s, const mtx_continuous_constants* k,
                                         mtx_continuous_plan* plan) {
  if (!plan->decide) return;
  for (int i = 0; i < 3; ++i) mtx_texel_stencil_of(s, &plan->at[i], k->width, k->height, 1, &plan->probe[i]);
}

/* The rest of the step (after mtx_continuous_agent_begin and mtx_continuous_plan_stencils,
 * with their plan). `sums` holds
 * one fixed-point plane per species (k->deposit_units per whole deposit of r_dep * dt). */
MTX_FN void mtx_continuous_agent_finish(MTX_TABLES s, MTX_GLOBAL const float* u,
                                        MTX_GLOBAL const float* field, MTX_GLOBAL mtx_i32* sums,
                                        MTX_GLOBAL const float* bias, mtx_walker* w, mtx_agent_life* life,
                                        mtx_u32 species, mtx_u64 agent, const mtx_continuous_constants* k,
                                        const mtx_continuous_plan* plan) {
  const float move_length = plan->move_length, sensor_length = plan->sensor_length;
  const float sensor_cos = plan->sensor_cos, sensor_sin = plan->sensor_sin, turn_impulse = plan->turn_impulse;
  const float activation_time = plan->activation_time, born = plan->born;
  const mtx_i32 deposit_units = plan->deposit_units;
  /* Sensors read the field where they read the concentration (the intrinsic lattice's
   * nodes); the obstacle test of a move reads it at the point's cell. */
  MTX_GLOBAL const float* sensed_field = s.lattice ? s.lattice_field : field;
  /* Turn decisions at f_i: each one senses and turns by the impulse omega / f_i (Jones'
   * rule: straight while the front is strongest, a random side when both sides beat
   * the front, else toward the stronger side; all equal: straight). The first one's
   * sensors were traced in the plan; later ones (a step longer than 1 / f_i) trace anew
   * from the turned heading. */
  if (plan->decide) {
    mtx_u64 rng = mtx_rng_init_keyed(k->decide_key, agent, k->step);
    for (int d = 0; d < MTX_MAX_DECISIONS_PER_STEP && life->clock >= k->decision_period; ++d) {
      life->clock -= k->decision_period;
      mtx_texel_stencil fresh[3];
      if (d > 0) mtx_continuous_probes(s, w, sensor_cos, sensor_sin, sensor_length, k, fresh);
      const mtx_texel_stencil* st = d > 0 ? fresh : plan->probe;
      const float left = mtx_continuous_read(u, sensed_field, &st[0], species, k);
      const float front = mtx_continuous_read(u, sensed_field, &st[1], species, k);
      const float right = mtx_continuous_read(u, sensed_field, &st[2], species, k);
      const float coin = mtx_rng_float(&rng);
      float side = 0.0f;
      if (front > left && front > right)
        side = 0.0f;
      else if (front < left && front < right)
        side = coin < 0.5f ? 1.0f : -1.0f;
      else if (left > right)
        side = 1.0f;
      else if (right > left)
        side = -1.0f;
      if (side != 0.0f) {
        const float turn = side * turn_impulse;
        w->heading = mtx_unit(mtx_rotate(w->heading, cos(turn), sin(turn)));
      }
    }
    if (life->clock >= k->decision_period) life->clock = 0.0f; /* aliasing: drop the rest */
  }

  /* Directional bias (§3.3, Fig. 6): turn toward the nearest of the n copies of the
   * triangle's bias direction; the angle phi to it obeys dphi/dt = -rate |b| phi, so the
   * step turns by phi (1 - exp(-rate |b| dt)): the same at any dt. */
  if (k->bias_on) {
    MTX_GLOBAL const float* b = bias + 2 * w->triangle;
    const float bx = b[0], by = b[1];
    const float length = sqrt(bx * bx + by * by);
    if (length > 0.0f) {
      float phi = atan2(w->heading.x * by - w->heading.y * bx, w->heading.x * bx + w->heading.y * by);
      const float sector = 6.28318530718f / MTX_CAST(float, k->bias_symmetry);
      phi -= sector * floor(phi / sector + 0.5f);
      const float turn = phi * (1.0f - exp(-k->bias_rate * length * k->dt));
      w->heading = mtx_unit(mtx_rotate(w->heading, cos(turn), sin(turn)));
    }
  }

  /* Move v * dt in pieces of at most max_piece texels, depositing an equal share at the end
   * of each piece: over successive steps the deposits sit evenly along the whole path,
   * r_dep / v per unit length, whatever dt or the piece count (Eq. 4). A piece that
   * would enter an obstacle from free ground is undone and the agent turns back. */
  MTX_GLOBAL const float* tpu = s.texels_per_unit + 2 * w->triangle;
  const float texels_moved = move_length * mtx_max(tpu[0], tpu[1]);
  /* Capped while still a float: a sliver's texels per unit can be huge (a triangle with
   * next to no area under a big UV patch), past what an int holds. */
  const float wanted = ceil(texels_moved / k->max_piece);
  const int pieces = wanted >= MTX_CAST(float, MTX_MAX_DEPOSIT_PIECES) ? MTX_MAX_DEPOSIT_PIECES
                     : (wanted >= 1.0f ? MTX_CAST(int, wanted) : 1);
  const float piece = move_length / MTX_CAST(float, pieces);
  const float piece_time = k->dt / MTX_CAST(float, pieces);
  /* Piece i covers ages born + [i, i + 1) dt / pieces: it deposits when its middle is
   * past the activation time, so activation starts within the step, not a step late. */
  const int deposits = k->deposit_on && deposit_units > 0 && life->age >= activation_time;
  MTX_GLOBAL mtx_i32* own = sums + species * k->plane_cells;
  const mtx_i32 share = deposit_units / pieces, extra = deposit_units - share * pieces;
  for (int i = 0; i < pieces; ++i) {
    const mtx_walker before = *w;
    if (mtx_walk_until(s.frames, s.adjacency, w, piece, 0, 0, k->absorb ? MTX_BOUNDARY_STOP : MTX_BOUNDARY_BOUNCE, 0) < 0) {
      /* Absorbed by an open boundary: the agent ends here and is reborn next step. */
      life->exposure = 0.0f;
      life->threshold = 0.0f;
      break;
    }
    if (MTX_FIELDS && k->has_fields) {
      const mtx_u32 texel = mtx_point_cell(s, w, k->width, k->height);
      if (field[texel] < MTX_OBSTACLE_THRESHOLD) {
        const mtx_u32 was = mtx_point_cell(s, &before, k->width, k->height);
        if (!(field[was] < MTX_OBSTACLE_THRESHOLD)) {
          *w = before;
          w->heading.x = -w->heading.x;
          w->heading.y = -w->heading.y;
        }
        continue;
      }
    }
    if (!deposits || born + (MTX_CAST(float, i) + 0.5f) * piece_time < activation_time) continue;
    mtx_texel_stencil st;
    mtx_texel_stencil_of(s, w, k->width, k->height, 0, &st);
    /* Piece i's whole share: the pieces' shares add up to exactly deposit_units. */
    if (st.count > 0) mtx_texel_deposit(own, &st, share + (i < extra ? 1 : 0), MTX_CAST(int, k->exclusive_sums));
  }
}

/* One step of agent `agent` (walker w, clocks life, species `species`): the three parts
 * in a row. `sums` holds one fixed-point plane per species. */
MTX_FN void mtx_continuous_agent_step(MTX_TABLES s, MTX_GLOBAL const float* u,
                                      MTX_GLOBAL const float* field, MTX_GLOBAL mtx_i32* sums,
                                      MTX_GLOBAL const float* alias_prob,
                                      MTX_GLOBAL const mtx_u32* alias_index,
                                      MTX_GLOBAL const float* bias, MTX_GLOBAL const float* maps,
                                      MTX_GLOBAL const float* spawn_max, mtx_walker* w,
                                      mtx_agent_life* life, mtx_u32 species, mtx_u64 agent,
                                      const mtx_continuous_constants* k) {
  mtx_continuous_plan plan;
  mtx_continuous_agent_begin(s, alias_prob, alias_index, bias, maps, spawn_max, w, life, agent, k, &plan);
  if (plan.decide) mtx_continuous_traces(s, w, plan.sensor_cos, plan.sensor_sin, plan.sensor_length, plan.at);
  mtx_continuous_plan_stencils(s, k, &plan);
  mtx_continuous_agent_finish(s, u, field, sums, bias, w, life, species, agent, k, &plan);
}

MTX_END_NAMESPACE

#endif
