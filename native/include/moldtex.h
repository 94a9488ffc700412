/* moldtex.h — the one public header of libmoldtex, the Moldtex simulation core.
 *
 * Conventions (modelled on Embree's rtc* and SQLite's C APIs):
 *  - Opaque handles with create/release pairs. A simulation keeps its surface alive,
 *    so the caller may release the surface right after creating the simulation.
 *  - Every call that can fail returns a moldtex_status; MOLDTEX_OK is 0.
 *    moldtex_last_error() explains the last failure *on the calling thread* in words
 *    a user can act on. No C++ exception ever crosses this boundary.
 *  - Parameter structs start with struct_size; fill them with the matching *_init
 *    function first, so an old caller keeps working when fields are appended.
 *  - Every input is validated (finite numbers, index ranges, sizes, memory needed).
 *  - A handle may be used from one thread at a time; different handles are independent.
 *
 * Units (docs/ARCHITECTURE.md has the reasoning):
 *  - One step is one tick of the paper's 60 Hz clock by default (time_step = 1/60 s).
 *  - Lengths on the surface are measured in texels: one texel is the mean 3D length
 *    that one texel of the chosen texture covers on this mesh,
 *    sqrt(surface area / (UV area * width * height)). Agents walk in true 3D lengths.
 */
#ifndef MOLDTEX_H
#define MOLDTEX_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Exported when building the library (MOLDTEX_BUILDING, set by its CMake target);
 * imported, or plain declarations, for those who use it. */
#if defined(_WIN32)
#if defined(MOLDTEX_BUILDING)
#define MOLDTEX_API __declspec(dllexport)
#else
#define MOLDTEX_API __declspec(dllimport)
#endif
#elif defined(MOLDTEX_BUILDING)
#define MOLDTEX_API __attribute__((visibility("default")))
#else
#define MOLDTEX_API
#endif

/* Bumped whenever a struct layout or a function signature changes incompatibly. */
#define MOLDTEX_ABI_VERSION 1u

/* The release: the one place it is written. CMake reads these lines (the project's
 * version) and stages the add-on with them (bl_info, blender_manifest.toml). */
#define MOLDTEX_VERSION_MAJOR 0
#define MOLDTEX_VERSION_MINOR 1
#define MOLDTEX_VERSION_PATCH 0
#define MOLDTEX_STRINGIFY_(x) #x
#define MOLDTEX_STRINGIFY(x) MOLDTEX_STRINGIFY_(x)
#define MOLDTEX_VERSION_STRING                                                            \
  MOLDTEX_STRINGIFY(MOLDTEX_VERSION_MAJOR) "." MOLDTEX_STRINGIFY(MOLDTEX_VERSION_MINOR) "." \
      MOLDTEX_STRINGIFY(MOLDTEX_VERSION_PATCH)

typedef enum moldtex_status {
  MOLDTEX_OK = 0,
  MOLDTEX_ERROR_INVALID_ARGUMENT = 1, /* null pointer, NaN, out-of-range value or index */
  MOLDTEX_ERROR_INVALID_MESH = 2,     /* no faces, bad indices, non-manifold edges, ... */
  MOLDTEX_ERROR_MISSING_UVS = 3,      /* no UVs, or a UV layout with zero area */
  MOLDTEX_ERROR_TOO_LARGE = 4,        /* the request would need absurd memory or sizes */
  MOLDTEX_ERROR_OUT_OF_MEMORY = 5,    /* an allocation failed */
  MOLDTEX_ERROR_INTERNAL = 6,         /* a bug: please report the message */
  MOLDTEX_ERROR_UNAVAILABLE = 7,      /* the requested backend or device cannot be used */
  MOLDTEX_ERROR_IO = 8,               /* a file could not be read or written */
  MOLDTEX_ERROR_BUSY = 9,             /* a bake is running on this simulation */
  MOLDTEX_ERROR_CANCELLED = 10        /* the caller cancelled the work (a domain build) */
} moldtex_status;

typedef struct moldtex_surface_t* moldtex_surface;
typedef struct moldtex_sim_t* moldtex_sim;
typedef struct moldtex_bake_t* moldtex_bake;
typedef struct moldtex_intrinsic_t* moldtex_intrinsic;
typedef struct moldtex_context_t* moldtex_context;

/* ---- library --------------------------------------------------------------------- */

/* A context owns what the simulations made in it share: the cache of intrinsic domains
 * (the last two built, by mesh, texture size and bound; moldtex_domain_info.from_cache).
 * moldtex_sim_create and moldtex_domain_build_start use the process's default context;
 * their _in variants take one. Releasing a context drops its cache; the simulations and
 * builds made in it keep what they use. moldtex_context_clear drops the cached domains
 * (NULL: the default context's). */
MOLDTEX_API moldtex_status moldtex_context_create(moldtex_context* out_context);
MOLDTEX_API void moldtex_context_release(moldtex_context context);
MOLDTEX_API moldtex_status moldtex_context_clear(moldtex_context context);
/* How many intrinsic domains the context's cache holds (NULL: the default context's). */
MOLDTEX_API moldtex_status moldtex_context_cached_domains(moldtex_context context, uint32_t* count);

/* MOLDTEX_ABI_VERSION of the loaded library; callers compare it with their own. */
MOLDTEX_API uint32_t moldtex_abi_version(void);
/* MOLDTEX_VERSION_STRING of the loaded library, e.g. "0.1.0". Static storage. */
MOLDTEX_API const char* moldtex_version_string(void);
/* Message of the last failed call on this thread ("" if none). Valid until the next
 * call on this thread. */
MOLDTEX_API const char* moldtex_last_error(void);

/* ---- surface: a triangle mesh with a UV layout ------------------------------------ */

typedef struct moldtex_mesh_desc {
  uint32_t struct_size;
  const float* positions;       /* vertex_count * 3 floats (x, y, z) */
  uint32_t vertex_count;
  const uint32_t* triangles;    /* triangle_count * 3 vertex indices */
  uint32_t triangle_count;
  const float* uvs;             /* uv_count * 2 floats (u, v); v = 0 is the image bottom.
                                   NULL with uv_count 0: the mesh has no UV map. It can
                                   still run on the intrinsic domain (read its result with
                                   moldtex_sim_read_vertex_rgba); the texture domain
                                   refuses it (MOLDTEX_ERROR_MISSING_UVS). */
  uint32_t uv_count;
  /* triangle_count * 3 indices into uvs (e.g. Blender loop indices of each loop
   * triangle). NULL means uvs are given per corner: uv_count == 3 * triangle_count. */
  const uint32_t* triangle_uvs;
} moldtex_mesh_desc;

MOLDTEX_API void moldtex_mesh_desc_init(moldtex_mesh_desc* desc);

/* Builds adjacency across UV seams (triangles that share a 3D edge are neighbours),
 * per-triangle frames and metric tensors. Refuses non-manifold edges (an edge shared
 * by more than two triangles), out-of-range indices, non-finite numbers, meshes with
 * no faces or zero area, and layouts with zero UV area. Zero-area triangles are
 * allowed but agents treat them as walls. */
MOLDTEX_API moldtex_status moldtex_surface_create(const moldtex_mesh_desc* desc,
                                                  moldtex_surface* out_surface);
MOLDTEX_API void moldtex_surface_release(moldtex_surface surface);

typedef struct moldtex_surface_info {
  uint32_t struct_size;
  uint32_t vertex_count;
  uint32_t triangle_count;
  uint32_t boundary_edge_count;     /* edges with one triangle: agents bounce there */
  uint32_t seam_edge_count;         /* shared 3D edges whose two sides have different UVs */
  uint32_t degenerate_triangle_count;
  double area;                      /* total 3D area */
  double uv_area;                   /* total UV area (unit square = 1) */
  /* Appended (older callers pass the smaller struct_size and get the fields above). */
  uint32_t generated_uvs;           /* 1: the mesh came without UVs; the surface holds a
                                       placeholder layout, one island per triangle */
} moldtex_surface_info;

MOLDTEX_API void moldtex_surface_info_init(moldtex_surface_info* info);
MOLDTEX_API moldtex_status moldtex_surface_get_info(moldtex_surface surface,
                                                    moldtex_surface_info* info);

/* Metric tensor g(t) of a triangle: the 2x2 symmetric matrix (row-major) such that
 * a UV displacement d has 3D length sqrt(d^T g d). */
MOLDTEX_API moldtex_status moldtex_surface_get_metric(moldtex_surface surface,
                                                      uint32_t triangle, float g[4]);

/* A point on the surface: a triangle and barycentric weights of its three corners
 * (non-negative, summing to 1). */
typedef struct moldtex_surface_point {
  uint32_t triangle;
  float bary[3];
} moldtex_surface_point;

/* 3D position and UV of a surface point. Either output may be NULL. */
MOLDTEX_API moldtex_status moldtex_surface_evaluate(moldtex_surface surface,
                                                    const moldtex_surface_point* point,
                                                    float position[3], float uv[2]);

/* Walks a straightest path over the surface (the tangent step): starts at `start`,
 * heads along `direction` (3D, projected onto the start triangle's plane), and
 * travels `length` 3D units, unfolding across edges and bouncing at open boundaries.
 * `end` receives the final point. If path_xyz is not NULL it receives up to
 * path_capacity 3D points: the start, each edge crossing or bounce, and the end;
 * *path_count (if not NULL) receives how many points the full path has. */
MOLDTEX_API moldtex_status moldtex_surface_trace(moldtex_surface surface,
                                                 const moldtex_surface_point* start,
                                                 const float direction[3], float length,
                                                 moldtex_surface_point* end,
                                                 float* path_xyz, uint32_t path_capacity,
                                                 uint32_t* path_count);

/* Bakes values given per triangle corner (triangle_count * 3 corners * 4 floats) into a
 * width x height RGBA float image over the UV layout (Blender's order, row 0 bottom):
 * each texel inside a UV island gets the barycentric interpolation of its triangle's
 * corner values; gutter texels copy the island texel across the seam (as the
 * simulation's gutter does); texels outside stay 0.
 * width and height: 8 .. 16384 each, as for a simulation; corner_float_count must be
 * triangle_count * 12 and every corner value finite; float_count is the capacity of
 * rgba in floats and must be >= width * height * 4. Corner order: corner k of triangle
 * t is the k-th index of triangle t in the moldtex_mesh_desc. */
MOLDTEX_API moldtex_status moldtex_surface_rasterize_corners(moldtex_surface surface,
    uint32_t width, uint32_t height, const float* corner_rgba, size_t corner_float_count,
    float* rgba, size_t float_count);

/* ---- simulation (MoMaS, momas-paper.md Algorithm 1) ------------------------------- */

/* Where the simulation runs. */
typedef enum moldtex_backend {
  MOLDTEX_BACKEND_AUTO = 0,   /* OpenCL on the first GPU device if there is one and it
                                 works, otherwise the CPU; moldtex_sim_get_backend_name
                                 says which and why */
  MOLDTEX_BACKEND_CPU = 1,    /* all cores of this machine */
  MOLDTEX_BACKEND_OPENCL = 2  /* the OpenCL device (opencl_platform, opencl_device) */
} moldtex_backend;

/* Choices that need a reset to change. */
typedef struct moldtex_sim_config {
  uint32_t struct_size;
  uint32_t width, height;  /* pheromone texture size in texels, 8 .. 16384 each */
  uint32_t agent_count;    /* 1 .. 67108864 */
  uint64_t seed;           /* same seed => bit-identical results for any thread count
                              (CPU) or for a given device (OpenCL) */
  /* Added after ABI 1's first release; older callers get the defaults. */
  uint32_t backend;          /* a moldtex_backend */
  uint32_t opencl_platform;  /* indices as listed by moldtex_opencl_get_device */
  uint32_t opencl_device;
  /* Added for species, fields and starting seeds (momas-paper.md §2.5); older callers
   * get the defaults. */
  uint32_t species_count;    /* 1 .. MOLDTEX_MAX_SPECIES (default 1): agent i belongs to
                                species i % species_count; each species has its own
                                pheromone channel */
  uint32_t seed_shape;       /* a moldtex_seed_shape (default MOLDTEX_SEED_RANDOM) */
  moldtex_surface_point seed_center; /* CIRCLE, BIG_BANG, STARBURST: the centre */
  float seed_radius;         /* CIRCLE, STARBURST: radius in 3D units of the mesh, measured
                                on the surface (geodesic); finite, > 0 */
  uint32_t seed_rays;        /* STARBURST: number of rays, 1 .. 1024 (default 8) */
  /* Optional static fields at create time (NULL = none): width * height * 4 floats as
   * moldtex_sim_set_fields takes them, copied during the call (not kept). Needed for
   * MOLDTEX_SEED_SPAWN_MAP, whose first spawn happens in moldtex_sim_create.
   * moldtex_sim_get_config returns NULL here. */
  const float* fields_rgba;
  /* Added for the continuous model; older callers get MOLDTEX_MODEL_MOMAS. */
  uint32_t model;            /* a moldtex_model */
  /* Added for the intrinsic domain (issue 11); older callers get the texture domain. */
  uint32_t domain;           /* a moldtex_domain */
  float intrinsic_bound;     /* MOLDTEX_DOMAIN_INTRINSIC: the largest circumradius of an
                                intrinsic triangle, in mesh units; 0 (default) = the mean
                                3D spacing of the island texels, so both domains resolve
                                the same detail (a mesh without UVs: the spacing of
                                width * height texels spread over its area) */
  /* Added for a simulation finer than its image (issue 9); older callers get 1. The
   * texture domain then runs at detail * width by detail * height texels, and every
   * texel array of this API stays width x height: moldtex_sim_read_rgba, the image
   * files and the texel classes give each image texel the mean of its detail^2
   * simulated texels (those on or beside an island), and fields and maps given per image
   * texel apply to all of them. A simulation at detail 2 is the one at twice the size
   * (the same agents, seed and length unit) seen at this size. 0 or 1 (none), 2 or 4;
   * above 1 MoMaS only, and detail * width and detail * height at most 16384. In
   * surface units, where a pattern unit spans under about two image texels, detail 2
   * keeps what one texel per unit cannot: a UV sphere's poles (README, "Units: Surface"). */
  uint32_t detail;
} moldtex_sim_config;

/* Where concentrations live (a config field: changing it needs a new simulation). Both
 * write the object's UV texture every frame. */
typedef enum moldtex_domain {
  MOLDTEX_DOMAIN_TEXTURE = 0,   /* the texels of the UV layout (every model) */
  MOLDTEX_DOMAIN_INTRINSIC = 1  /* the vertices of an intrinsic Delaunay triangulation of
                                   the mesh (layton-intrinsic-slime.md §3.1): no UV seams,
                                   no UV distortion. The continuous model and Gray-Scott
                                   only, on both backends; the mesh must be manifold */
} moldtex_domain;

/* The behaviour model, chosen at create (a config field, so changing it needs a new
 * simulation). */
typedef enum moldtex_model {
  MOLDTEX_MODEL_MOMAS = 0,      /* momas-paper.md Algorithm 1 (moldtex_sim_params) */
  MOLDTEX_MODEL_CONTINUOUS = 1, /* layton-intrinsic-slime.md §3.2: rate-based agents, a
                                   diffusion-decay PDE, line-integrated deposits, agent
                                   turnover (moldtex_continuous_params) */
  MOLDTEX_MODEL_GRAY_SCOTT = 2  /* Gray-Scott reaction-diffusion, no agents
                                   (moldtex_reaction_params) */
} moldtex_model;

/* How agents are placed at create and reset. All placements are a pure function of the
 * config's seed. Agents placed inside an obstacle (CIRCLE, BIG_BANG, STARBURST only) may
 * walk out of it; no agent ever walks into one. */
typedef enum moldtex_seed_shape {
  MOLDTEX_SEED_RANDOM = 0,    /* uniform by 3D area, headings uniform (obstacle texels
                                 excluded when fields mark obstacles) */
  MOLDTEX_SEED_SPAWN_MAP = 1, /* a texel with probability ~ R (spawn weight) * its 3D
                                 area, obstacles excluded, a uniform point inside it;
                                 needs fields whose spawn weights are not all zero */
  MOLDTEX_SEED_CIRCLE = 2,    /* on the geodesic circle of radius seed_radius around
                                 seed_center, heading toward the centre */
  MOLDTEX_SEED_BIG_BANG = 3,  /* all at seed_center, headings uniform */
  MOLDTEX_SEED_STARBURST = 4  /* seed_rays rays from seed_center (equal angles), each agent
                                 at a uniform distance in [0, seed_radius] along its ray,
                                 heading outward */
} moldtex_seed_shape;

#define MOLDTEX_MAX_SPECIES 4u

/* Parameters that may change between steps without a reset. Ranges in brackets are
 * the ones momas-paper.md Table 1 tested; the core accepts the wider hard limits. */
typedef struct moldtex_sim_params {
  uint32_t struct_size;
  float movement_speed;   /* delta_a: texels travelled per step [1, 2]; hard 0 .. 64 */
  float turn_speed;       /* theta_a: a turn is r * turn_speed * pi * time_step radians,
                             r ~ U[0,1) [10, 50]; hard 0 .. 1000 */
  float vision_distance;  /* delta_s: sensor distance in units of 10 texels [0.4, 2];
                             hard 0 .. 50 */
  float vision_angle;     /* theta_s: sensor angle in degrees [10, 50]; hard 0 .. 180 */
  float evaporation_rate; /* epsilon_d: pheromone lost per second [0.2, 1]; hard 0 .. 1000 */
  float diffusion_rate;   /* blur weight per second: each step mixes
                             min(1, diffusion_rate * time_step) of a 3x3 Gaussian blur */
  float deposit;          /* pheromone an agent leaves: texel = max(texel, deposit), 0 .. 1 */
  float time_step;        /* seconds per step, 1/60 by default; hard (0, 1] */
  uint32_t substeps;      /* deposits along each move (line-integrated trail), 1 .. 64 */
  uint32_t thread_count;  /* 0 = all cores; results do not depend on it */
  /* Food with hunger (plasmodial-slime-readme.md, "Food Sources"); appended, so a caller
   * whose struct ends at thread_count gets these defaults (feature off). */
  float hunger_rate;      /* hunger gained per second, h = min(1, h + hunger_rate *
                             time_step) each step; 0 (default) = off: food is ignored and
                             results equal a simulation without food bit for bit;
                             hard 0 .. 1000 */
  float food_radius;      /* 3D distance (mesh units) within which an agent eats: its
                             hunger resets to 0 and, for a finite source, it consumes one
                             unit; default 0.1; hard 0 .. 1e6 */
  /* Sensing kernel; appended, so a caller whose struct ends at food_radius gets 0. */
  uint32_t sensor_size;   /* r in texels: each sensor sums the (2r+1)^2 texels around the
                             texel under it, clamped to the texture, as MoMaS' reference
                             code does; 0 (default) = that one texel, bit for bit as before
                             the field existed; hard 0 .. 4 */
  /* Pattern lengths in surface units; appended, so a caller whose struct ends at
   * sensor_size gets 0. 0 (default) = "texel" means the mean 3D length of one texel at
   * this resolution (the MoMaS behaviour, bit for bit as before the field existed).
   * > 0: the 3D length (mesh units) that one "texel" of movement_speed, vision_distance
   * and sensor_size stands for, whatever the resolution, and the texture domain measures
   * the surface: a step moves movement_speed * length_unit * 60 * time_step (simulated
   * time, not step count, sets the result); the blur becomes surface diffusion with the
   * 3x3 Gaussian's reach in 3D (variance diffusion_rate * time_step / 2 * length_unit^2
   * per axis and step, whatever the texel size, through every UV seam, open boundaries
   * closed); a deposit marks every texel within half a length_unit of the agent (at most
   * 8 texels each side; where part of that square lies off the UV island -- gutter, a UV
   * pole's teeth, a seam, an open boundary -- it grows until one square length_unit of
   * island is marked). So 512^2, 1024^2 and 2048^2 show the same cells, sharper.
   * Finite, <= 10 * sqrt(surface area). */
  float length_unit;
} moldtex_sim_params;

MOLDTEX_API void moldtex_sim_config_init(moldtex_sim_config* config);
MOLDTEX_API void moldtex_sim_params_init(moldtex_sim_params* params);

/* Parameters of the continuous model (layton-intrinsic-slime.md Table 1), all rates
 * per simulated second and all lengths in mesh units (the caller applies the object's
 * scale and any pattern scale). They may change between steps; they apply to every
 * species (species keep their attractions: an agent of species s senses
 * sum_k attraction[k] * u_k + fields). moldtex_sim_params' thread_count, hunger and food
 * still apply; its MoMaS fields are ignored by this model.
 *
 * Pheromone is a concentration u (amount per unit of 3D area) obeying
 *   du/dt = r_dif * Laplacian(u) - r_dec * u + deposits           (Eq. 1)
 * on the surface, through every UV seam, with closed open boundaries. Each step an
 * agent deposits r_dep * time_step spread evenly along the path it walked (Eq. 4).
 * moldtex_sim_read_rgba and moldtex_sim_write_image give u / U (1 = the uniform
 * steady state of Eq. 5) when U is finite and positive, else u itself. */
typedef struct moldtex_continuous_params {
  uint32_t struct_size;
  float move_rate;        /* v: mesh units per second; 0 .. 1e6 */
  float turn_rate;        /* omega: radians per second; 0 .. 1e6 */
  float turn_frequency;   /* f_i: turn decisions per second; turning accumulates and is
                             applied as one impulse of omega / f_i each 1 / f_i seconds,
                             timed per agent; (0, 1e6] */
  float sensor_distance;  /* d: mesh units along the surface; 0 .. 1e6 */
  float sensor_angle;     /* theta: degrees, -180 .. 180 (negative: chemo-repulsion) */
  float deposit_rate;     /* r_dep: amount per agent per second; 0 .. 1e12 */
  float diffusion_rate;   /* r_dif: mesh units^2 per second; 0 .. 1e6 */
  float decay_rate;       /* r_dec: per second; 0 .. 1e6 */
  float mean_lifetime;    /* tau: seconds; 0 = no turnover (agents live for ever) */
  float activation_time;  /* t_a: an agent deposits only from this age on; seconds, >= 0 */
  float time_step;        /* dt: seconds per step; (0, 1] */
  uint32_t integrator;    /* a moldtex_integrator */
  /* Directional bias (§3.3, Fig. 6), with the vectors of moldtex_sim_set_bias: each step
   * an agent turns toward the nearest of `bias_symmetry` copies of its triangle's bias
   * direction (rotated by 360 / n degrees each) at bias_strength * |vector| * (angle to
   * it) radians per second (integrated exactly over the step). 0 = off. */
  float bias_strength;    /* per second; 0 .. 1e6 */
  uint32_t bias_symmetry; /* n, 1 .. 6 (default 1) */
  uint32_t bias_spawn;    /* 1: agents (re)spawned by turnover face one of the n bias
                             directions of their triangle (Fig. 8), where it has one;
                             0 (default): a uniform heading */
  /* Added with the parameter maps; older callers get the default. */
  uint32_t boundary;      /* a moldtex_boundary: what an agent does at an open edge */
} moldtex_continuous_params;

typedef enum moldtex_boundary {
  MOLDTEX_BOUNDARY_REFLECT = 0, /* turns back into the surface (default) */
  MOLDTEX_BOUNDARY_ABSORB = 1   /* dies there and is reborn (a sink along the mesh's open
                                   edges, Fig. 18), even with no turnover elsewhere */
} moldtex_boundary;

typedef enum moldtex_integrator {
  MOLDTEX_INTEGRATOR_AUTO = 0,     /* forward Euler while it needs at most 64 sub-steps per
                                      step for stability, else backward Euler */
  MOLDTEX_INTEGRATOR_FORWARD = 1,  /* forward Euler (Eq. 2), sub-stepped for stability
                                      (at most 256 sub-steps; beyond that refused) */
  MOLDTEX_INTEGRATOR_BACKWARD = 2  /* backward Euler (Eq. 3), conjugate gradients */
} moldtex_integrator;

/* Defaults: a Jones-like look at a sensor distance of 0.09 mesh units. */
MOLDTEX_API void moldtex_continuous_params_init(moldtex_continuous_params* params);
MOLDTEX_API moldtex_status moldtex_sim_set_continuous_params(moldtex_sim sim,
    const moldtex_continuous_params* params);
MOLDTEX_API moldtex_status moldtex_sim_get_continuous_params(moldtex_sim sim,
    moldtex_continuous_params* params);
/* The bias field of the continuous model: triangle_count * 3 floats, one 3D vector per
 * triangle (in the order of moldtex_mesh_desc), projected onto its triangle; its length
 * weights bias_strength there (1 = full, 0 = none). NULL clears it (no bias). Values must
 * be finite with length <= 1e6. Kept across moldtex_sim_reset and in checkpoints. */
MOLDTEX_API moldtex_status moldtex_sim_set_bias(moldtex_sim sim, const float* vectors,
                                                size_t float_count);

/* ---- Gray-Scott reaction-diffusion (MOLDTEX_MODEL_GRAY_SCOTT) ---------------------
 * Two chemicals U and V per island texel obey
 *   dU/dt = D_u Laplacian(U) - U V^2 + F (1 - U)
 *   dV/dt = D_v Laplacian(V) + U V^2 - (F + k) V
 * on the surface (the continuous model's texel Laplacian: 3D areas, through every UV
 * seam, open boundaries closed), by forward Euler with equal sub-steps per step:
 * (1 + F + k) dt_sub <= 0.5 and max(D_u, D_v) dt_sub rate <= 0.5 for 99% of the texels
 * (rate: the texel's sum of conductances over its 3D area), but no more than 4x the
 * sub-steps the median texel needs. Stiffer texels (the thin ones at UV poles) take
 * their own diffusion loss implicitly, so they follow their neighbours instead of
 * blowing up (slightly slower diffusion there). A step needing more than 4096 sub-steps
 * is refused: lower time_step or the diffusion rates. Values stay finite and >= 0. Every
 * cell reads the previous sub-step only: bit-identical for any thread count.
 * The model has no agents: config.agent_count and species_count are ignored (the
 * simulation reports 0 agents and 2 planes). Plane 0 is V, plane 1 is U:
 * moldtex_sim_read_rgba gives R = V, G = U, B = 0, A = the island mask; images have the
 * channels R (V) and G (U). The start (create and reset) is U = 1, V = 0 with
 * seed_count small disks (radius seed_radius, mesh units, 3D distance) of V = 1 and
 * U = 0.5, centred at random points chosen from config.seed: uniform by 3D area, or by
 * the fields' spawn weights (R) with seed_shape MOLDTEX_SEED_SPAWN_MAP.
 * Stats: coverage = mean V, presence = area fraction where V > 0.1. */
typedef struct moldtex_reaction_params {
  uint32_t struct_size;
  float feed;            /* F: per second, 0 .. 1 (default 0.035) */
  float kill;            /* k: per second, 0 .. 1 (default 0.065) */
  float diffusion_u;     /* D_u: mesh units^2 per second, 0 .. 1e6 (default 2e-5) */
  float diffusion_v;     /* D_v: mesh units^2 per second, 0 .. 1e6 (default 1e-5) */
  float time_step;       /* seconds per step, (0, 100] (default 1) */
  uint32_t seed_count;   /* starting disks, 1 .. 1024 (default 8); used at reset */
  float seed_radius;     /* mesh units, > 0, < 1e30 (default 0.05); used at reset */
} moldtex_reaction_params;

/* Defaults: spots (F 0.035, k 0.065) with the classic pixel-unit rates D_u = 0.2,
 * D_v = 0.1 on a lattice of 0.01 mesh units (a pattern scale s gives D = 0.2 s^2). */
MOLDTEX_API void moldtex_reaction_params_init(moldtex_reaction_params* params);
/* Takes effect at the next step (seed_count and seed_radius at the next reset). Kept under
 * other models but unused there. */
MOLDTEX_API moldtex_status moldtex_sim_set_reaction_params(moldtex_sim sim,
    const moldtex_reaction_params* params);
MOLDTEX_API moldtex_status moldtex_sim_get_reaction_params(moldtex_sim sim,
    moldtex_reaction_params* params);

/* One pair of calls for every model's own parameters: `params` points to the parameter
 * struct of `model` (a moldtex_model), which begins with its struct_size:
 * moldtex_sim_params for MoMaS, moldtex_continuous_params for the continuous model,
 * moldtex_reaction_params for Gray-Scott. A simulation keeps the parameters of every
 * model and uses those of the one it runs. The same as the calls per model above
 * (moldtex_sim_set_params, moldtex_sim_set_continuous_params, ...), which stay. */
MOLDTEX_API moldtex_status moldtex_sim_set_model_params(moldtex_sim sim, uint32_t model, const void* params);
MOLDTEX_API moldtex_status moldtex_sim_get_model_params(moldtex_sim sim, uint32_t model, void* params);

/* Parameter maps and stimuli of the continuous model (layton-intrinsic-slime.md §3.3,
 * Eq. 6/7, Fig. 7, 8): per texel values in the order of moldtex_sim_read_rgba (width *
 * height floats, one per texel; gutter texels are ignored and take the texel across their
 * seam). Agents read a map at the texel they stand on. The multipliers (MOVE_RATE ..
 * SPAWN, DIFFUSION_RATE, DECAY_RATE) are in 0 .. 1000 and scale their parameter where
 * the agent (or the cell) is:
 *   DIFFUSION_RATE r_dif per cell: the face between two cells conducts with the mean of
 *                  their values (0 on both sides: a wall the pheromone cannot cross)
 *   DECAY_RATE     r_dec per cell (U and the stimuli's unit keep the global r_dec)
 *   MEAN_LIFETIME  0 = a sink: an agent there decays at once (even with no turnover
 *                  elsewhere, mean_lifetime 0), and is reborn by the spawn map
 *   SPAWN          where turnover re-spawns agents: density ~ 3D area * weight (a source)
 * The stimuli are signed, within +-1e6, in units of U (Eq. 5):
 *   READ_STIMULUS  sensed on top of the trails by every species (1 = as strong as the
 *                  uniform steady state); never diffuses or decays
 *   WRITE_STIMULUS adds (or, negative, removes) pheromone at value * r_dec * U per second
 *                  in every species' plane, which then diffuses and decays with the rest
 *                  (alone it would hold u / U = value)
 * Gray-Scott reads DIFFUSION_RATE (both D_u and D_v, per face as above), FEED and KILL
 * (multipliers of F and k per texel, the products capped at 1); the other models ignore
 * FEED and KILL.
 * NULL clears a map. Maps are kept across moldtex_sim_reset and in checkpoints; the
 * MoMaS model ignores all but READ_STIMULUS. */
typedef enum moldtex_map {
  MOLDTEX_MAP_MOVE_RATE = 0,
  MOLDTEX_MAP_TURN_RATE = 1,
  MOLDTEX_MAP_SENSOR_DISTANCE = 2,
  MOLDTEX_MAP_SENSOR_ANGLE = 3,
  MOLDTEX_MAP_DEPOSIT_RATE = 4,
  MOLDTEX_MAP_MEAN_LIFETIME = 5,
  MOLDTEX_MAP_ACTIVATION_TIME = 6,
  MOLDTEX_MAP_SPAWN = 7,
  MOLDTEX_MAP_READ_STIMULUS = 8,
  MOLDTEX_MAP_WRITE_STIMULUS = 9,
  MOLDTEX_MAP_DIFFUSION_RATE = 10,
  MOLDTEX_MAP_DECAY_RATE = 11,
  MOLDTEX_MAP_FEED = 12,
  MOLDTEX_MAP_KILL = 13,
  MOLDTEX_MAP_COUNT = 14
} moldtex_map;
MOLDTEX_API moldtex_status moldtex_sim_set_map(moldtex_sim sim, uint32_t map, const float* values,
                                               size_t count);
/* Copies map `map` into values (width * height floats); *is_set = 0 (and values
 * untouched) when the map is not set. */
MOLDTEX_API moldtex_status moldtex_sim_get_map(moldtex_sim sim, uint32_t map, float* values, size_t count,
                                               uint32_t* is_set);

/* Behaviour of one species (momas-paper.md §2.5). Same meaning, units and hard ranges as
 * the fields of moldtex_sim_params with the same names. An agent of species s senses
 *   sum_k attraction[k] * P_k + fields
 * where P_k is species k's pheromone (k < species_count; the rest is ignored): +1 follows
 * that trail, -1 avoids it. Each attraction is in [-1, 1]. */
typedef struct moldtex_species_params {
  uint32_t struct_size;
  float movement_speed, turn_speed, vision_distance, vision_angle;
  float deposit;   /* into the species' own channel */
  float attraction[4];
} moldtex_species_params;

/* Defaults of species `species`: the behaviour of moldtex_sim_params_init, attraction
 * +1 to its own trail and -1 to every other species' (the paper's competing species). */
MOLDTEX_API void moldtex_species_params_init(moldtex_species_params* params, uint32_t species);

/* Creates a simulation on the surface's UV layout, takes config->fields_rgba if given,
 * and spawns agents as config->seed_shape says (by default uniformly by area with
 * headings over the full circle). Every species starts with `params`' behaviour and the
 * default attractions (moldtex_species_params_init). The simulation holds its own
 * reference to the surface. */
MOLDTEX_API moldtex_status moldtex_sim_create(moldtex_surface surface,
                                              const moldtex_sim_config* config,
                                              const moldtex_sim_params* params,
                                              moldtex_sim* out_sim);
/* The same in `context` (NULL: the default one; see moldtex_context_create). */
MOLDTEX_API moldtex_status moldtex_sim_create_in(moldtex_context context, moldtex_surface surface,
                                                 const moldtex_sim_config* config, const moldtex_sim_params* params,
                                                 moldtex_sim* out_sim);
MOLDTEX_API void moldtex_sim_release(moldtex_sim sim);

/* Sets the shared parameters and the behaviour fields (movement_speed, turn_speed,
 * vision_distance, vision_angle, deposit) of ALL species, leaving their attractions: a
 * one-species caller needs nothing else. get_params returns species 0's behaviour. */
MOLDTEX_API moldtex_status moldtex_sim_set_params(moldtex_sim sim,
                                                  const moldtex_sim_params* params);
MOLDTEX_API moldtex_status moldtex_sim_get_params(moldtex_sim sim, moldtex_sim_params* params);
/* Behaviour of species `index` (0 .. species_count - 1); takes effect at the next step. */
MOLDTEX_API moldtex_status moldtex_sim_set_species_params(moldtex_sim sim, uint32_t index,
                                                          const moldtex_species_params* params);
MOLDTEX_API moldtex_status moldtex_sim_get_species_params(moldtex_sim sim, uint32_t index,
                                                          moldtex_species_params* params);

/* Static fields (momas-paper.md §2.5), painted in texture space: width * height * 4
 * floats in the order of moldtex_sim_read_rgba. Per texel:
 *   R  spawn weight >= 0 (MOLDTEX_SEED_SPAWN_MAP, used at the next reset)
 *   G  obstacle where > 0.5: every species senses -1e9 there, nothing is deposited there,
 *      and an agent never moves into it (a move that would end there is undone and the
 *      agent turns back)
 *   B  attractor strength in [0, 1]: sensed as (species_count + 1) * B on top of the
 *      trails, more than any trail sum but finite, so patterns still form inside
 *   A  ignored
 * Fields never diffuse or evaporate; they stay until set again (NULL rgba clears them).
 * Gutter texels take the obstacle and attractor of the texel across the seam (or are an
 * obstacle where painted so), so sensing across a seam sees walls. All values must be
 * finite. With seed_shape SPAWN_MAP, fields with no spawn weight outside obstacles are
 * refused. */
MOLDTEX_API moldtex_status moldtex_sim_set_fields(moldtex_sim sim, const float* rgba,
                                                  size_t float_count);
MOLDTEX_API moldtex_status moldtex_sim_get_config(moldtex_sim sim, moldtex_sim_config* config);

/* Food sources (plasmodial-slime-readme.md, "Food Sources"), active while hunger_rate > 0.
 * Every agent has a hunger h in [0, 1] (0 at spawn). After its MoMaS turn, a hungry agent
 * (h > 0) blends its heading toward the nearest source that still has food, at 3D
 * distance d: w = min(1, h^8 * strength / d^2), heading = normalize((1 - w) * heading +
 * w * toward), `toward` being the 3D direction to the source projected into the agent's
 * triangle. Within food_radius it eats instead: h = 0 and, when amount >= 0, one unit is
 * consumed per eating agent per step (counted exactly, so deterministic on any backend),
 * clamped at 0. A source with amount 0 neither attracts nor feeds. */
#define MOLDTEX_MAX_FOOD_SOURCES 64u
typedef struct moldtex_food_source {
  float position[3]; /* a point on or near the surface, mesh units */
  float strength;    /* attractor strength c >= 0 (mesh units squared) */
  float amount;      /* food left; < 0 = inexhaustible */
} moldtex_food_source;
/* Replaces all sources (0 .. MOLDTEX_MAX_FOOD_SOURCES; count 0 clears). Values must be
 * finite and strength >= 0. Kept across moldtex_sim_reset (amounts are not refilled). */
MOLDTEX_API moldtex_status moldtex_sim_set_food(moldtex_sim sim, const moldtex_food_source* sources,
                                                uint32_t count);
/* Current sources with their remaining amounts: writes min(capacity, count) of them and
 * the number of sources to *count. */
MOLDTEX_API moldtex_status moldtex_sim_get_food(moldtex_sim sim, moldtex_food_source* sources,
                                                uint32_t capacity, uint32_t* count);

/* What the simulation runs on, e.g. "CPU (2 threads)" or "OpenCL: <device>
 * (<platform>)", followed for Auto by why OpenCL was not used. Copies at most
 * capacity - 1 bytes and a terminating NUL. */
MOLDTEX_API moldtex_status moldtex_sim_get_backend_name(moldtex_sim sim, char* buffer,
                                                        size_t capacity);

/* Clears the pheromone and respawns the agents from the config's seed and seed shape
 * (a spawn map from the current fields). Fields and species parameters are kept; agents
 * added by slime brushes and the brushes' undo stashes are dropped. */
MOLDTEX_API moldtex_status moldtex_sim_reset(moldtex_sim sim);
/* Advances `steps` steps (sense, turn, move, deposit, blur, evaporate). One call runs at
 * most MOLDTEX_MAX_STEPS_PER_CALL steps, so no call holds its caller for days: a larger
 * count is refused (MOLDTEX_ERROR_INVALID_ARGUMENT) with nothing stepped; step in
 * chunks, or run in the background with moldtex_sim_run_start (which can be stopped). */
#define MOLDTEX_MAX_STEPS_PER_CALL 100000u
MOLDTEX_API moldtex_status moldtex_sim_step(moldtex_sim sim, uint32_t steps);

/* Live stepping on the core's own thread (Blender's Start grows the mold this way while
 * the interface redraws; no caller code runs on that thread). moldtex_sim_run_start steps
 * in chunks of about chunk_seconds (0 < s <= 10) of work, from the measured cost of a step
 * (step_seconds_hint > 0 seeds it; 0 = unknown, the first chunk is one step), until
 * moldtex_sim_run_stop, or by itself after limit_seconds (0 < s <= 3600) should nobody
 * come back for it. Meanwhile every other call on the simulation answers
 * MOLDTEX_ERROR_BUSY except these three. Steps run this way are the steps
 * moldtex_sim_step would run: the same seed gives the same state. */
typedef struct moldtex_run_progress {
  uint32_t struct_size;
  uint32_t running;        /* 1 while the thread steps */
  uint64_t steps;          /* steps run since moldtex_sim_run_start */
  double step_seconds;     /* the running mean cost of one step */
} moldtex_run_progress;

MOLDTEX_API void moldtex_run_progress_init(moldtex_run_progress* progress);
MOLDTEX_API moldtex_status moldtex_sim_run_start(moldtex_sim sim, double chunk_seconds, double limit_seconds,
                                                 double step_seconds_hint);
/* Thread-safe; returns at once. MOLDTEX_ERROR_INVALID_ARGUMENT if no run was started. */
MOLDTEX_API moldtex_status moldtex_sim_run_get_progress(moldtex_sim sim, moldtex_run_progress* progress);
/* Stops after the current chunk (at most 1000 steps) and waits; `progress` (may be NULL)
 * receives the run's last progress. Returns MOLDTEX_OK, or the error a step raised. A
 * simulation without a run answers MOLDTEX_OK with steps = 0. */
MOLDTEX_API moldtex_status moldtex_sim_run_stop(moldtex_sim sim, moldtex_run_progress* progress);

/* Copies the pheromone as RGBA float, Blender's order (row 0 is the bottom row, each
 * row left to right): width * height * 4 floats. With one species R = G = B = the
 * pheromone in [0, 1]; A is 1 on the islands and their gutter (a mask). With 2 to 4
 * species channel k holds species k's pheromone, unused channels are 0, and A is the
 * mask while species_count < 4 (with 4 species A is species 3). Texels just
 * outside the UV islands (the gutter) hold copies of their neighbours across the seam;
 * all other outside texels are 0 in every channel.
 * `float_count` is the capacity of `rgba` in floats and must be >= width*height*4. */
MOLDTEX_API moldtex_status moldtex_sim_read_rgba(moldtex_sim sim, float* rgba,
                                                 size_t float_count);

/* The pheromone at each vertex of the input mesh (moldtex_mesh_desc's vertices),
 * encoded as moldtex_sim_read_rgba encodes a texel: 4 floats per vertex, A = 1 for a
 * vertex of the surface and 0 (all channels) for a vertex no triangle uses. Intrinsic
 * domain only (the input vertices are vertices of its triangulation; the texture domain
 * answers MOLDTEX_ERROR_INVALID_ARGUMENT): this is how a mesh without UVs shows its
 * pattern, as a colour per vertex. `float_count` must be >= vertex_count * 4. */
MOLDTEX_API moldtex_status moldtex_sim_read_vertex_rgba(moldtex_sim sim, float* rgba,
                                                        size_t float_count);

/* Texel classes of the layout (same order as the pheromone): 0 outside, 1 inside a UV
 * island, 2 gutter. `count` must be >= width * height. */
#define MOLDTEX_TEXEL_OUTSIDE 0u
#define MOLDTEX_TEXEL_INSIDE 1u
#define MOLDTEX_TEXEL_GUTTER 2u
MOLDTEX_API moldtex_status moldtex_sim_read_texel_classes(moldtex_sim sim, uint8_t* classes,
                                                          size_t count);

/* Current agent positions: writes min(capacity, agent_count) points. The order is not
 * stable across steps (backends regroup agents in memory for speed). */
MOLDTEX_API moldtex_status moldtex_sim_read_agents(moldtex_sim sim,
                                                   moldtex_surface_point* points,
                                                   uint32_t capacity);

typedef struct moldtex_sim_stats {
  uint32_t struct_size;
  uint64_t step_count;     /* steps since create or reset */
  uint32_t agent_count;    /* live agents (the slime brushes add and erase some) */
  uint64_t bytes_in_use;   /* memory held by the simulation and its surface */
  double coverage;         /* momas-paper.md Eq. 1: mean pheromone over the islands,
                              weighted by 3D area; with several species the mean over
                              species of each one's Eq. 1 */
  double presence;         /* Eq. 1 with the ceiling: 3D-area fraction where pheromone > 0
                              (of any species) */
  /* Continuous model (0 for MoMaS); appended. */
  double u_metric;         /* U of layton-intrinsic-slime.md Eq. 5 per species:
                              N_s r_dep / (r_dec A) exp(-t_a / tau), N_s the live agents of
                              a species (species 0), A the surface area; +inf if r_dec = 0 */
  double mean_concentration; /* 3D-area-weighted mean of species 0's concentration u */
  double time;             /* simulated seconds since create or reset */
} moldtex_sim_stats;

MOLDTEX_API void moldtex_sim_stats_init(moldtex_sim_stats* stats);
MOLDTEX_API moldtex_status moldtex_sim_get_stats(moldtex_sim sim, moldtex_sim_stats* stats);

/* The simulation's domain (issue 11). For the texture domain only `domain` and
 * `cell_count` (island texels) are set. */
typedef struct moldtex_domain_info {
  uint32_t struct_size;
  uint32_t domain;            /* a moldtex_domain */
  uint32_t cell_count;        /* cells the concentration lives in: island texels or
                                 intrinsic vertices */
  uint32_t face_count;        /* intrinsic triangles */
  double bound;               /* circumradius bound used (mesh units) */
  double build_seconds;       /* wall time of the build: triangulation, operators and
                                 texel map */
  uint64_t insertions;        /* circumcentres inserted, boundary splits included */
  uint32_t skipped_faces;     /* triangles left above the bound by the guards (small
                                 input angles, round-off) */
  uint32_t from_cache;        /* 1: this simulation reused a recent build of the same
                                 mesh, texture size and bound (no build time spent) */
} moldtex_domain_info;

MOLDTEX_API void moldtex_domain_info_init(moldtex_domain_info* info);
MOLDTEX_API moldtex_status moldtex_sim_get_domain_info(moldtex_sim sim, moldtex_domain_info* info);

/* The intrinsic domain's vertices (tests and tools; MOLDTEX_ERROR_INVALID_ARGUMENT on the
 * texture domain). vertex_count must be moldtex_domain_info.cell_count. xyz_area (NULL:
 * skipped) receives 4 floats per vertex: its 3D position on the mesh and its lumped area
 * (a third of its triangles' areas; 0 for a vertex no triangle uses); values (NULL:
 * skipped) receives species_count planes of vertex_count concentrations as the
 * simulation holds them (the image shows them divided by U under the continuous model;
 * Gray-Scott's planes are V, then U). */
MOLDTEX_API moldtex_status moldtex_sim_read_intrinsic_vertices(moldtex_sim sim, float* xyz_area, float* values,
                                                             uint32_t vertex_count);
/* The intrinsic triangles: 3 vertex indices each, counter-clockwise; face_count must be
 * moldtex_domain_info.face_count. */
MOLDTEX_API moldtex_status moldtex_sim_read_intrinsic_faces(moldtex_sim sim, uint32_t* corners,
                                                          uint32_t face_count);

/* Building the intrinsic domain ahead, with progress and cancel. The triangulation of a
 * big mesh takes seconds (about 10 s for 100 k triangles at 1024^2), too long to block an
 * interface in moldtex_sim_create. moldtex_domain_build_start builds, on its own thread,
 * the domain a simulation of this surface and config would run on (config as for
 * moldtex_sim_create, domain MOLDTEX_DOMAIN_INTRINSIC; thread_count as its params'), and
 * keeps it in its context's cache: a moldtex_sim_create in that context with the same
 * surface, texture size and bound then reuses it (moldtex_domain_info.from_cache = 1)
 * while the cache holds it (the last two builds). The surface may be released meanwhile (the build keeps it). */
typedef struct moldtex_domain_build_t* moldtex_domain_build;

typedef enum moldtex_build_stage {
  MOLDTEX_BUILD_TEXTURE = 0,    /* the texels of the UV islands */
  MOLDTEX_BUILD_REFINING = 1,   /* the intrinsic Delaunay triangulation, refined */
  MOLDTEX_BUILD_OPERATORS = 2,  /* numbering, Laplacian, the locator for agents */
  MOLDTEX_BUILD_TEXEL_MAP = 3,  /* every island texel located on it */
  MOLDTEX_BUILD_DONE = 4
} moldtex_build_stage;

typedef struct moldtex_domain_build_progress {
  uint32_t struct_size;
  uint32_t state;          /* a moldtex_bake_state: running, finished, cancelled, failed */
  uint32_t stage;          /* a moldtex_build_stage */
  uint32_t vertex_count;   /* intrinsic vertices so far */
  double fraction;         /* 0..1 of the whole build: an estimate that only grows */
  double seconds;          /* since the start */
  uint32_t from_cache;     /* 1: finished at once, the cache held it */
  char message[512];       /* why it failed */
} moldtex_domain_build_progress;

MOLDTEX_API void moldtex_domain_build_progress_init(moldtex_domain_build_progress* progress);
/* Checks the config at once (as moldtex_sim_create would, and refuses the texture domain
 * and MoMaS; the seed and the fields do not matter here), then starts the build. */
MOLDTEX_API moldtex_status moldtex_domain_build_start(moldtex_surface surface, const moldtex_sim_config* config,
                                                      uint32_t thread_count, moldtex_domain_build* out_build);
/* The same in `context` (NULL: the default one). */
MOLDTEX_API moldtex_status moldtex_domain_build_start_in(moldtex_context context, moldtex_surface surface,
                                                         const moldtex_sim_config* config, uint32_t thread_count,
                                                         moldtex_domain_build* out_build);
/* Thread-safe; returns at once. */
MOLDTEX_API moldtex_status moldtex_domain_build_get_progress(moldtex_domain_build build,
                                                             moldtex_domain_build_progress* progress);
/* Asks the build to stop (within about a millisecond of refinement); nothing of it is kept.
 * Returns at once. */
MOLDTEX_API void moldtex_domain_build_cancel(moldtex_domain_build build);
/* Blocks until the build ends: MOLDTEX_OK when finished, MOLDTEX_ERROR_CANCELLED when
 * cancelled, else its error (moldtex_last_error says why). */
MOLDTEX_API moldtex_status moldtex_domain_build_wait(moldtex_domain_build build);
/* Cancels and waits if still running, then frees the handle. */
MOLDTEX_API void moldtex_domain_build_release(moldtex_domain_build build);

/* ---- images, checkpoints and bakes ------------------------------------------------ */

typedef enum moldtex_image_format {
  MOLDTEX_IMAGE_EXR_HALF = 0,   /* OpenEXR, 16-bit float, zip compressed */
  MOLDTEX_IMAGE_EXR_FLOAT = 1,  /* OpenEXR, 32-bit float, zip compressed */
  MOLDTEX_IMAGE_PNG8 = 2,
  MOLDTEX_IMAGE_PNG16 = 3
} moldtex_image_format;

/* Writes the current pheromone to `path` through OpenImageIO: one channel per species
 * (a single species is one luminance channel "Y"; 2 to 4 species are channels "R", "G",
 * "B", "A" in species order), top row first as image files store it. The file is written as `path`.partial and renamed when complete, so `path` either
 * does not exist or is whole. */
MOLDTEX_API moldtex_status moldtex_sim_write_image(moldtex_sim sim, const char* path,
                                                   uint32_t format);

/* A checkpoint holds the whole state: agents (with their species and hunger), every species'
 * pheromone, step count, parameters, species parameters, fields and food. Loading it into a
 * simulation made from the same mesh and config (resolution, agent count, seed, species
 * count) restores that state exactly,
 * so the following steps equal those of an uninterrupted run. Written atomically.
 * The live agents are saved whatever their number (slime brushes change it; a checkpoint
 * may hold 0 .. 2^26 agents), but not the brush batches: after loading, every agent
 * counts as spawned (batch 0) and moldtex_sim_undo_agents has nothing to undo. */
MOLDTEX_API moldtex_status moldtex_sim_save_checkpoint(moldtex_sim sim, const char* path);
MOLDTEX_API moldtex_status moldtex_sim_load_checkpoint(moldtex_sim sim, const char* path);

/* A bake renders frames first_frame..last_frame into `directory` as
 * <file_prefix><frame, 4 digits>.<exr|png>: it resets the simulation, then before each
 * frame advances steps_per_frame steps, so frame f shows the state after
 * (f - first_frame + 1) * steps_per_frame steps. Beside the frames it keeps
 * <file_prefix>metrics.csv (frame, step, coverage, presence; momas-paper.md Eq. 1) and,
 * if write_checkpoints, <file_prefix>checkpoint.bin after every frame. With `resume`,
 * it continues after the last frame of that checkpoint, giving exactly the frames an
 * uninterrupted bake gives. It runs on its own thread; the simulation answers
 * MOLDTEX_ERROR_BUSY to other calls until the bake ends. */
typedef struct moldtex_bake_desc {
  uint32_t struct_size;
  const char* directory;    /* must exist */
  const char* file_prefix;  /* default "moldtex_" */
  int32_t first_frame, last_frame; /* 0 <= first <= last <= 999999 */
  uint32_t steps_per_frame; /* 1 .. 100000 */
  uint32_t format;          /* a moldtex_image_format */
  uint32_t write_checkpoints;
  uint32_t resume;
} moldtex_bake_desc;

typedef enum moldtex_bake_state {
  MOLDTEX_BAKE_RUNNING = 0,
  MOLDTEX_BAKE_FINISHED = 1,
  MOLDTEX_BAKE_CANCELLED = 2,
  MOLDTEX_BAKE_FAILED = 3
} moldtex_bake_state;

typedef struct moldtex_bake_progress {
  uint32_t struct_size;
  uint32_t state;            /* a moldtex_bake_state */
  int32_t first_frame, last_frame;
  int32_t last_frame_written; /* first_frame - 1 before any */
  uint32_t frames_done;      /* whole frames on disk, from this and resumed runs */
  uint64_t step_count;
  double coverage, presence; /* of the last frame written */
  char message[512];         /* why it failed, if it failed */
} moldtex_bake_progress;

MOLDTEX_API void moldtex_bake_desc_init(moldtex_bake_desc* desc);
MOLDTEX_API void moldtex_bake_progress_init(moldtex_bake_progress* progress);
MOLDTEX_API moldtex_status moldtex_bake_start(moldtex_sim sim, const moldtex_bake_desc* desc,
                                              moldtex_bake* out_bake);
/* Thread-safe; returns at once. */
MOLDTEX_API moldtex_status moldtex_bake_get_progress(moldtex_bake bake,
                                                     moldtex_bake_progress* progress);
/* Asks the bake to stop after the current step; no partial frame is left. Returns at once. */
MOLDTEX_API void moldtex_bake_cancel(moldtex_bake bake);
/* Blocks until the bake ends; returns its outcome (MOLDTEX_OK if finished or cancelled). */
MOLDTEX_API moldtex_status moldtex_bake_wait(moldtex_bake bake);
/* Cancels and waits if still running, then frees the handle. */
MOLDTEX_API void moldtex_bake_release(moldtex_bake bake);

/* ---- OpenCL devices ------------------------------------------------------------- */

typedef struct moldtex_opencl_device_info {
  uint32_t struct_size;
  uint32_t platform_index, device_index; /* for moldtex_sim_config */
  uint32_t is_gpu;
  uint64_t global_memory_bytes;
  char name[256];
  char platform_name[256];
} moldtex_opencl_device_info;

MOLDTEX_API void moldtex_opencl_device_info_init(moldtex_opencl_device_info* info);
/* Number of OpenCL devices on all platforms. Without a usable OpenCL runtime this
 * returns MOLDTEX_ERROR_UNAVAILABLE, sets *count to 0, and moldtex_last_error() says
 * why (e.g. which package to install). */
MOLDTEX_API moldtex_status moldtex_opencl_device_count(uint32_t* count);
/* Device number `index` (0 .. count-1) of that list. */
MOLDTEX_API moldtex_status moldtex_opencl_get_device(uint32_t index,
                                                     moldtex_opencl_device_info* info);

/* ---- spatial --------------------------------------------------------------------- */

/* Ray casts and closest points through Embree 3. The first query on a surface builds a
 * BVH that is kept with the surface handle and freed by moldtex_surface_release.
 * Triangles the surface treats as degenerate (zero 3D or UV area, see
 * moldtex_surface_info) are not in it, so every answer is a point that brushes and
 * moldtex_surface_trace accept. Both queries are thread-safe on one surface handle. */
typedef struct moldtex_ray_hit {
  uint32_t struct_size;
  uint32_t hit;                  /* 1 if the ray met the surface, else 0 (the rest is 0) */
  moldtex_surface_point point;   /* triangle and barycentrics (corner 0,1,2) of the nearest hit */
  float distance;                /* ray parameter s of the hit: origin + s * direction */
  float position[3];             /* 3D point of the hit */
  float uv[2];                   /* UV of the hit */
  float normal[3];               /* unit geometric normal of the hit triangle (by winding) */
} moldtex_ray_hit;
MOLDTEX_API void moldtex_ray_hit_init(moldtex_ray_hit* hit);
/* Nearest hit of origin + s*direction, 0 <= s <= max_distance (max_distance may be
 * INFINITY), front and back faces alike. origin and direction must be finite with every
 * component within +-1e18 (Embree's representable range), direction of length >= 1e-18
 * (any length in between: s is in units of it), max_distance >= 0. Anything else is
 * refused with MOLDTEX_ERROR_INVALID_ARGUMENT. A miss returns MOLDTEX_OK with
 * hit->hit == 0. */
MOLDTEX_API moldtex_status moldtex_surface_ray_cast(moldtex_surface surface,
    const float origin[3], const float direction[3], float max_distance, moldtex_ray_hit* hit);
/* Nearest point of the surface to `position` (3D, finite, each coordinate within
 * +-1e18), exact (each candidate triangle's closest point in double precision); its 3D
 * distance in *distance (may be NULL). */
MOLDTEX_API moldtex_status moldtex_surface_closest_point(moldtex_surface surface,
    const float position[3], moldtex_surface_point* point, float* distance);

/* ---- brushes --------------------------------------------------------------------- */

/* A brush dab: a geodesic disk around `center`. Distances d are path lengths along
 * straightest paths from the centre (moldtex_surface_trace's walk, across seams into
 * every island the disk reaches; at open boundaries the paths bounce). The weight of a
 * point is w(d / radius) with w(x) = 1 for x <= 1 - falloff, then a smoothstep down to 0
 * at x = 1, and 0 beyond. The work of a dab is bounded by the mesh, not the radius: a
 * disk that holds all the surface its centre can reach (radius beyond the farthest
 * vertex) walks its paths only about twice that part's geodesic extent, which reaches
 * it all; weights still use the radius. */
typedef enum moldtex_brush_mode { MOLDTEX_BRUSH_PAINT = 0, MOLDTEX_BRUSH_ERASE = 1 } moldtex_brush_mode;
typedef struct moldtex_brush {
  uint32_t struct_size;
  moldtex_surface_point center;  /* where the dab lands (e.g. a ray hit); not on a
                                    zero-area triangle */
  float radius;                  /* geodesic radius in mesh units, >= 1e-30 and < 1e30 */
  float strength;                /* [0,1]: fraction of the way to the target at full weight */
  float falloff;                 /* [0,1]: 0 hard disk; 1 weight falls smoothly to 0 at the rim */
  uint32_t mode;                 /* moldtex_brush_mode (paint only; the agent calls ignore it) */
  uint32_t channel;              /* paint: RGBA channel 0..3; agents: species index */
  float value;                   /* paint target for PAINT (ERASE targets 0); finite */
} moldtex_brush;
/* radius 0.1, strength 1, falloff 0.5, PAINT, channel 0, value 1, centre (0, 1/3 each). */
MOLDTEX_API void moldtex_brush_init(moldtex_brush* brush);

/* One dab into a caller-owned RGBA float image (Blender's order, row 0 bottom) of
 * width x height (1 .. 65536 each; float_count >= width * height * 4) laid over the
 * surface's UV layout. Every texel reached by the disk (a texel holding a point of the
 * surface at d <= radius, found by sampling half a texel apart; a radius above 512
 * texel widths is sampled more coarsely, so that a dab stays cheap, and may miss
 * texels) moves toward the target once, with the smallest d that reaches it:
 * v += (target - v) * strength * w(d / radius). Texels are found with the simulation's
 * rule (texel = floor(uv * size)); gutter texels outside the islands are not touched.
 * *changed (may be NULL) = number of texels whose value changed. */
MOLDTEX_API moldtex_status moldtex_surface_paint(moldtex_surface surface, uint32_t width,
    uint32_t height, float* rgba, size_t float_count, const moldtex_brush* brush, uint32_t* changed);

/* Slime brush: adds `count` agents of species brush->channel (< species_count), uniform
 * over the disk (each walks from the centre at a uniform angle for r * sqrt(u), r the
 * radius or, for a disk larger than the reachable surface, the walk length above),
 * headings uniform, hunger 0, tagged with `batch` (1..65535; e.g. one per stroke). Agent
 * k of a batch depends only on (config seed, batch, k) (k counts the batch's agents
 * added before), so re-applying the same dabs after moldtex_sim_undo_agents gives the
 * same agents, on any backend and thread count. The total may not exceed 2^26 agents.
 * moldtex_sim_stats.agent_count reports the live count.
 * Gray-Scott (no agents): each dab moves the disk's texels toward a seed, V = 1 and
 * U = 0.5, by strength * w(d / radius) (count and channel are ignored); erasing moves
 * them toward V = 0, U = 1; moldtex_sim_undo_agents puts a stroke's texels back. */
MOLDTEX_API moldtex_status moldtex_sim_add_agents(moldtex_sim sim, const moldtex_brush* brush,
    uint32_t count, uint32_t batch);
/* Erase-slime brush: removes each agent standing within the disk (d <= radius) with
 * probability strength * w(d / radius), drawn deterministically (so with strength 1 and
 * falloff 0: exactly the agents in the disk), and keeps them, with their whole state,
 * under `batch` so moldtex_sim_undo_agents can put them back. *removed (may be NULL) =
 * how many. It may remove every agent: a simulation with 0 agents steps (the pheromone
 * only blurs and evaporates). */
MOLDTEX_API moldtex_status moldtex_sim_erase_agents(moldtex_sim sim, const moldtex_brush* brush,
    uint32_t batch, uint32_t* removed);
/* Undo of a brush stroke: removes the live agents added with `batch` and puts back those
 * erased with `batch` (they resume where they were, after the other agents), then
 * forgets the batch. A batch with nothing to undo is not an error. moldtex_sim_reset
 * drops every brush agent and every stash (back to config.agent_count spawned agents). */
MOLDTEX_API moldtex_status moldtex_sim_undo_agents(moldtex_sim sim, uint32_t batch);

/* ---- surface map tools (Layton et al. §6, Fig. 14-17) ---------------------------- */

/* Finite elements on the surface's vertices (piecewise-linear functions over the
 * triangles of moldtex_mesh_desc, vertex k = value k): the cotangent Laplacian and the
 * lumped (barycentric) mass matrix. Positions are shared across UV seams, so maps are
 * continuous there. Triangles with ~zero 3D area are skipped; a vertex that no other
 * triangle uses ("unused") gets 0 (the geodesic distance: -1, below). Connected
 * components are those of the non-degenerate triangles. Solves are sparse Cholesky
 * (LDL^T) factorisations in double precision, serial and deterministic, built on every
 * call (a million-vertex mesh needs a few hundred MB for a moment).
 *
 * Common rules: values (vertex_count floats, per vertex in the order of
 * moldtex_mesh_desc) must be finite with |value| <= 1e15; count must equal the
 * surface's vertex_count; out_count must be >= it (the extra entries are left alone).
 * Failures leave the output untouched. */

/* Geodesic distance (mesh units) from the vertices whose source weight is > 0.5, by the
 * heat method (Crane et al. 2013): heat flows for t = time_factor * h^2 (h the mean edge
 * length; time_factor 1 is the paper's choice, in (0, 1e6]; larger is smoother), then the
 * distance is the function whose gradient best fits the heat's normalised negative
 * gradient. Sources get exactly 0; no distance is negative. Vertices that no source can
 * reach over the surface (another connected component, or an unused vertex) get -1.
 * No source at all is an error (MOLDTEX_ERROR_INVALID_ARGUMENT). Mean error on a fine
 * sphere is ~1 %; distances are slightly too long near the cut locus and the source.
 * On meshes several hundred edges across from a small source, raise time_factor. */
MOLDTEX_API moldtex_status moldtex_surface_geodesic_distance(moldtex_surface surface,
    const float* source_weights, size_t vertex_count, float time_factor,
    float* out_distance, size_t out_count);

/* Laplace interpolation (Fig. 17): the harmonic map (discrete Laplacian 0 on every free
 * vertex) equal to values[i] wherever fixed[i] != 0: the smoothest blend between the
 * fixed regions. values of free vertices are ignored (they may be anything finite).
 * Free vertices in a connected component without a fixed vertex, and unused free
 * vertices, get 0. At least one vertex must be fixed. */
MOLDTEX_API moldtex_status moldtex_surface_laplace_interpolate(moldtex_surface surface,
    const float* values, const uint8_t* fixed, size_t count, float* out, size_t out_count);

/* Short-time diffusion (blur, Fig. 14): one backward-Euler step (M + time L) x = M values,
 * time in mesh units squared (>= 0, finite): the heat kernel has standard deviation
 * sqrt(2 time), so a blur of radius r is time = r^2 / 2. Conserves the area-weighted
 * integral; time 0 returns values; times beyond 1000 x the surface area act as that. */
MOLDTEX_API moldtex_status moldtex_surface_diffuse_map(moldtex_surface surface,
    const float* values, size_t count, float time, float* out, size_t out_count);

/* Gradient of the piecewise-linear map: one 3D vector per triangle (out_float_count >=
 * triangle_count * 3, in triangle order), in the triangle's plane, exact for linear
 * functions; 0 on degenerate triangles. Usable as moldtex_sim_set_bias vectors (whose
 * length weights the bias: normalise them, or scale so the largest is 1, as needed; the
 * bias accepts lengths <= 1e6). Fails if a gradient does not fit in a float. */
MOLDTEX_API moldtex_status moldtex_surface_map_gradient(moldtex_surface surface,
    const float* values, size_t count, float* out_vectors, size_t out_float_count);

/* ---- colour map from an image (Layton et al. §3.4, Fig. 14, 16, 20) ------------- */

/* Finds a 1D parameterisation of an image's pixel colours and returns it as ColorRamp
 * stops: a deterministic subsample of sample_count pixels (evenly spread, jittered by
 * seed) is converted to CIELAB (D65) and reduced to one coordinate by Isomap (k-nearest-
 * neighbour graph in Lab, Dijkstra shortest paths, classical MDS: double centring and the
 * top eigenvector by power iteration). Pieces of the neighbour graph that do not touch
 * are joined by their closest pair of points. The coordinate (0.5th..99.5th percentile
 * -> 0..1) is binned into 48 bins whose mean Lab colours, lightly smoothed, are the knots
 * of a Catmull-Rom curve; stops are then placed greedily where a linear ramp between the
 * stops strays most (in Delta E, CIE76) from the curve, until the largest error is below
 * tolerance or max_stops are placed. Positions are proportional to perceptual distance
 * along the curve. Cost: O(sample_count^2 (neighbour_count + log sample_count)) time and
 * 8 * sample_count^2 bytes: ~0.45 s for 1500 samples, ~5 s for 4096 (one core), plus
 * one pass over the pixels (~0.05 s for 4K). */
typedef struct moldtex_colour_ramp_desc {
  uint32_t struct_size;
  uint32_t channels;        /* floats per pixel: 3 (RGB) or 4 (RGBA, alpha ignored); 4 */
  uint32_t srgb_encoded;    /* 1: values are sRGB-encoded (8-bit images), 0: linear; 0 */
  uint32_t sample_count;    /* pixels used, 16..4096 (fewer if the image is smaller); 1500 */
  uint32_t neighbour_count; /* k of the neighbour graph, 2..64; 10 */
  uint32_t max_stops;       /* 2..32 (Blender's ColorRamp holds 32); 32 */
  float tolerance;          /* Delta E (> 0, <= 100) at which no more stops are added; 1 */
  uint32_t reverse;         /* 0: the darker end (lower L*) at position 0; 1: lighter end */
  /* "Peak at": < 0 off (default -1); in [0, 1]: the ramp is re-parameterised (piecewise
   * linearly) so that the most saturated colour of the curve (largest chroma C*) sits
   * at this position (Fig. 14b). */
  float peak_position;
  uint64_t seed;            /* subsampling seed; fixed default */
} moldtex_colour_ramp_desc;

MOLDTEX_API void moldtex_colour_ramp_desc_init(moldtex_colour_ramp_desc* desc);

typedef struct moldtex_colour_stop {
  float position;           /* 0..1, increasing */
  float color[4];           /* linear RGB (scene linear, as ColorRamp stores it), alpha 1 */
} moldtex_colour_stop;

typedef struct moldtex_colour_ramp_info {
  uint32_t struct_size;
  uint32_t stop_count;      /* stops written */
  uint32_t sample_count;    /* pixels used */
  uint32_t component_count; /* pieces of the neighbour graph (1 = one connected curve) */
  /* How well one variable explains the image, 0..1: variance_explained times
   * continuity. Below ~0.7 (e.g. two unrelated colour clusters) one continuous ramp
   * does not describe the image well. */
  float explained;
  float variance_explained; /* 1 - mean squared Delta E to the curve / colour variance */
  float eigen_energy;       /* MDS: top eigenvalue / trace of the double-centred matrix */
  float mean_error;         /* mean Delta E of the samples from the fitted curve */
  float ramp_error;         /* largest Delta E of the linear ramp from the curve */
  /* 1 - (longest edge that had to join separate pieces of the neighbour graph) / (extent
   * of the 1D coordinate): near 1 for a continuous curve (also a posterised one, whose
   * many pieces join with short edges), low when the colours jump between groups. */
  float continuity;
} moldtex_colour_ramp_info;

MOLDTEX_API void moldtex_colour_ramp_info_init(moldtex_colour_ramp_info* info);

/* pixels: pixel_count * desc->channels finite floats (Blender's Image.pixels order; the
 * order does not matter beyond the subsample). At least 2 pixels; pixel_count *
 * channels <= 2^32. out_stops: capacity >= desc->max_stops entries. info may be NULL.
 * Refuses NULL pointers, NaN or infinite values (naming the pixel), negative values
 * below -1 and values above 1e6, and options outside their ranges. Nothing is written on
 * failure. */
MOLDTEX_API moldtex_status moldtex_colour_ramp_from_pixels(const float* pixels, size_t pixel_count,
    const moldtex_colour_ramp_desc* desc, moldtex_colour_stop* out_stops, uint32_t capacity,
    moldtex_colour_ramp_info* info);

/* ---- intrinsic Delaunay triangulation (issue 11) -------------------------------- */

/* An intrinsic triangulation of a surface's 3D mesh (Sharp, Soliman & Crane 2019): the
 * same surface, the same metric, but other edges: geodesic segments over the input
 * triangles, chosen so that every edge is Delaunay (all cotangent weights >= 0) and,
 * with a bound, every triangle has circumradius <= max_circumradius (Delaunay
 * refinement by circumcentre insertion and boundary edge splits). Vertices are the
 * input mesh's vertices (the positions of moldtex_mesh_desc, shared across UV seams:
 * seams do not cut it, open boundaries do) followed by the inserted ones. Every
 * intrinsic vertex has a point on the input mesh, and points map both ways.
 * Not yet a simulation domain: this exposes the triangulation only.
 * Input triangles that repeat a vertex index have no area and are not part of it.
 * Memory: about 0.5 KB per vertex. The handle keeps its surface alive. */
typedef struct moldtex_intrinsic_params {
  uint32_t struct_size;
  /* Largest circumradius of a triangle, in mesh units (finite, >= 0). 0: no refinement,
   * only the Delaunay edge flips of the input mesh; 0 */
  float max_circumradius;
  /* Cap on inserted vertices (circumcentres plus boundary splits), 1..16,000,000;
   * 4,000,000. A bound for which the expected vertex count (area / bound^2) exceeds it
   * is refused before building; reaching it while refining stops with
   * MOLDTEX_INTRINSIC_STOP_INSERTION_CAP (not an error: the triangulation is Delaunay,
   * some triangles are larger than the bound). */
  uint32_t max_insertions;
} moldtex_intrinsic_params;

MOLDTEX_API void moldtex_intrinsic_params_init(moldtex_intrinsic_params* params);

typedef enum moldtex_intrinsic_stop {
  MOLDTEX_INTRINSIC_STOP_CONVERGED = 0,     /* done (with a bound: every triangle within
                                               it, except those counted in *_left) */
  MOLDTEX_INTRINSIC_STOP_INSERTION_CAP = 1, /* max_insertions reached */
  MOLDTEX_INTRINSIC_STOP_FLIP_CAP = 2       /* the edge flips did not settle (a bug) */
} moldtex_intrinsic_stop;

/* Builds the triangulation: input mesh with mollified edge lengths (a margin of 1e-6 of
 * the mean edge length makes near-degenerate triangles valid), Delaunay edge flips,
 * then refinement if max_circumradius > 0. Refuses non-manifold meshes (an edge with
 * more than two triangles, two triangles winding an edge the same way, a vertex whose
 * triangles form more than one fan). Single-threaded. */
MOLDTEX_API moldtex_status moldtex_intrinsic_create(moldtex_surface surface,
                                                    const moldtex_intrinsic_params* params,
                                                    moldtex_intrinsic* out_intrinsic);
MOLDTEX_API void moldtex_intrinsic_release(moldtex_intrinsic intrinsic);

typedef struct moldtex_intrinsic_info {
  uint32_t struct_size;
  uint32_t vertex_count;         /* intrinsic vertices: input_vertex_count + inserted */
  uint32_t triangle_count;
  uint32_t edge_count;
  uint32_t input_vertex_count;   /* the surface's vertex_count */
  uint32_t input_triangle_count; /* input triangles in it (without repeated indices) */
  uint32_t dropped_triangle_count; /* input triangles that repeat a vertex index */
  uint32_t stop_reason;          /* moldtex_intrinsic_stop */
  uint64_t flips;                /* Delaunay edge flips, all stages */
  uint64_t insertions;           /* circumcentres inserted */
  uint64_t boundary_splits;      /* encroached boundary edges split at their midpoints */
  uint64_t given_up;             /* faces given up by round-off rechecks */
  /* Triangles left with a circumradius above the bound (0 without a bound): at input
   * corners sharper than 60 degrees (refining them would never end), and others. */
  uint32_t faces_over_bound_sharp;
  uint32_t faces_over_bound_other;
  double max_circumradius;       /* the bound used (0: none) */
  double largest_circumradius;   /* largest circumradius left */
  double area;                   /* total area of the intrinsic triangles */
  double mollify_epsilon;        /* length added to every edge */
  double build_seconds;          /* wall time of moldtex_intrinsic_create */
  char message[256];             /* what was done or why it stopped, for the user */
} moldtex_intrinsic_info;

MOLDTEX_API void moldtex_intrinsic_info_init(moldtex_intrinsic_info* info);
MOLDTEX_API moldtex_status moldtex_intrinsic_get_info(moldtex_intrinsic intrinsic,
                                                      moldtex_intrinsic_info* info);

/* Marks an intrinsic vertex without a point on the input mesh: an input vertex that
 * no triangle uses (moldtex_intrinsic_vertex_points). */
#define MOLDTEX_INTRINSIC_NO_TRIANGLE 0xffffffffu

/* Maps points on the input surface (triangle = index in moldtex_mesh_desc, barycentric
 * weights finite, >= 0, summing to 1) to the intrinsic triangulation (triangle = intrinsic
 * triangle index, weights of its corners). count: 1..16,777,216; out must hold count
 * points. A point in an input triangle that repeats a vertex index is refused. Nothing
 * is written on failure. Cost: a short trace per point (about a microsecond). */
MOLDTEX_API moldtex_status moldtex_intrinsic_locate(moldtex_intrinsic intrinsic,
                                                    const moldtex_surface_point* input_points,
                                                    uint32_t count,
                                                    moldtex_surface_point* out_intrinsic_points);
/* The inverse: intrinsic points (triangle < triangle_count) to points on the input mesh. */
MOLDTEX_API moldtex_status moldtex_intrinsic_to_input(moldtex_intrinsic intrinsic,
                                                      const moldtex_surface_point* intrinsic_points,
                                                      uint32_t count,
                                                      moldtex_surface_point* out_input_points);
/* Each intrinsic vertex's point on the input mesh (vertex_count of them; capacity must
 * be >= vertex_count, the rest is left alone). An input vertex is at its own corner;
 * unused input vertices get triangle MOLDTEX_INTRINSIC_NO_TRIANGLE and weights 0. */
MOLDTEX_API moldtex_status moldtex_intrinsic_vertex_points(moldtex_intrinsic intrinsic,
                                                           moldtex_surface_point* out_points,
                                                           uint32_t capacity);

#ifdef __cplusplus
}
#endif
#endif /* MOLDTEX_H */
