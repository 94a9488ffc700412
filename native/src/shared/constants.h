/* constants.h — numbers both backends must agree on. */
#ifndef MOLDTEX_SHARED_CONSTANTS_H
#define MOLDTEX_SHARED_CONSTANTS_H

#ifndef __OPENCL_C_VERSION__
#include "shared/portable.h"
#endif

/* Texel classes; equal to MOLDTEX_TEXEL_* of the public header. */
#define MTX_TEXEL_OUTSIDE 0
#define MTX_TEXEL_INSIDE 1
#define MTX_TEXEL_GUTTER 2

/* Enough crossings for any sane step; stops a walker caught in a degenerate vertex fan. */
#define MTX_MAX_CROSSINGS_PER_WALK 4096
/* Minimum sine between heading and edge after a crossing, so a walker grazing an edge
 * always enters the next triangle instead of bouncing between two forever. */
#define MTX_MIN_CROSSING_SINE 1e-4f
/* The paper's vision distance is in units of this many texels: Table 1's 0.4-2 becomes
 * 4-20 texels, around the classic 9-texel sensor offset. */
#define MTX_VISION_UNIT_TEXELS 10.0f
/* No neighbour across an edge: an open boundary, or a wall next to a zero-area face. */
#define MTX_NO_NEIGHBOUR 0xffffffffu
/* Species, each with its own pheromone plane; equal to MOLDTEX_MAX_SPECIES. */
#define MTX_MAX_SPECIES 4
/* Food sources; equal to MOLDTEX_MAX_FOOD_SOURCES. */
#define MTX_MAX_FOOD 64
/* What an obstacle texel adds to every species' sensing (momas-paper.md §2.5), and the
 * threshold below which a texel's field value marks an obstacle. */
#define MTX_OBSTACLE_FIELD (-1e9f)
#define MTX_OBSTACLE_THRESHOLD (-1e8f)
/* Surface units: a deposit footprint or a sensing square reaches at most this many
 * texels to each side (bounded work where texels are tiny, e.g. at UV poles). */
#define MTX_MAX_FOOTPRINT_TEXELS 8

MTX_BEGIN_NAMESPACE

/* Per-step constants of the MoMaS rules, derived from the parameters on the host.
 * Laid out with the 64-bit fields first so C++ and OpenCL C agree on the layout. */
typedef struct mtx_momas_constants {
  mtx_u64 seed;
  mtx_u64 step;
  mtx_u64 steer_key; /* mtx_rng_key(seed, MTX_RNG_STEER) */
  /* Per species. */
  float move_length[MTX_MAX_SPECIES];   /* 3D length of one decision's move */
  float sensor_length[MTX_MAX_SPECIES]; /* 3D distance to the sensors */
  float sensor_cos[MTX_MAX_SPECIES], sensor_sin[MTX_MAX_SPECIES];
  float max_turn[MTX_MAX_SPECIES];      /* radians */
  /* attraction[4 * s + k]: weight of species k's pheromone in species s's sensing. */
  float attraction[MTX_MAX_SPECIES * MTX_MAX_SPECIES];
  mtx_u32 substeps;
  mtx_u32 width, height;
  mtx_u32 species_count;
  mtx_u32 has_fields;  /* 0: the field plane is all zero and is not read */
  mtx_u32 food_count;  /* food sources with food left (0 while hunger is off) */
  float hunger_step;   /* hunger gained per step; 0 = food with hunger is off */
  float food_radius;   /* 3D distance within which an agent eats */
  mtx_u32 sensor_size; /* sensing square radius r in texels: (2r+1)^2 texels; 0 = one */
  /* Surface units (moldtex_sim_params.length_unit > 0): the 3D length of one pattern
   * "texel"; deposits mark a footprint of that size and the sensing square scales with it.
   * 0 = MoMaS' texel units. */
  float length_unit;
  mtx_u32 surface_mode;
  /* Surface units: the turn's random part r - 1/2 is scaled by sqrt((1/60 s) / the time
   * between decisions), so the heading's random walk has the variance per simulated
   * second it has at 1/60 s. 1 (MoMaS' turn exactly) wherever agents decide once per
   * 1/60 s tick (`coast`, `decisions`); else only where a step holds no whole number of
   * ticks. */
  float turn_jitter;
  /* 1 where agents only move this step, without sensing or turning (surface units at a
   * time step under 1/60 s: agents decide on MoMaS' own 60 Hz tick, momas_decides in
   * agents/momas_rules); 0, as zeroed constants have it, where they decide. */
  mtx_u32 coast;
  /* Decisions (sense, turn, move a share of the step) per step: 0 or 1 is one; a step
   * over 1/60 s in surface units makes one per MoMaS tick (momas_constants). */
  mtx_u32 decisions;
} mtx_momas_constants;

MTX_END_NAMESPACE

#endif
