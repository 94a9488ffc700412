// libFuzzer target for the C API (issue 14): bytes become meshes, UVs, parameters, ray
// queries, brushes and damaged checkpoints. The API must answer every call with a known
// status and, on failure, a message; it must never crash, hang or touch memory it does
// not own (AddressSanitizer and UBSan watch that), and whatever it accepted must keep the
// simulation's values finite.
//
// Input: byte 0 picks the mode.
//   even: a mesh from the bytes, then up to 24 operations on it (see Op).
//   odd:  a valid checkpoint of a small simulation, patched by the bytes, then loaded.
// Numbers are read little-endian from the front (missing bytes read as 0), so seeds are
// easy to write (native/fuzz/corpus/, made by native/fuzz/make_corpus.py).
//
// Build: cmake -DMOLDTEX_FUZZ=ON with clang (tools/run_sanitizers.sh does it).
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include <unistd.h>

#include "moldtex.h"

namespace {

struct Bytes {
  const uint8_t* data;
  size_t size, at = 0;
  bool empty() const { return at >= size; }
  uint8_t u8() { return at < size ? data[at++] : 0; }
  uint16_t u16() { return static_cast<uint16_t>(u8() | (u8() << 8)); }
  uint32_t u32() { return static_cast<uint32_t>(u16()) | (static_cast<uint32_t>(u16()) << 16); }
  float f32() {
    const uint32_t bits = u32();
    float f;
    std::memcpy(&f, &bits, 4);
    return f;
  }
};

[[noreturn]] void bug(const char* what) {
  std::fprintf(stderr, "moldtex fuzz: %s (last error: %s)\n", what, moldtex_last_error());
  std::abort();
}

// Every call answers a known status, and a failure comes with a message.
moldtex_status check(moldtex_status st) {
  if (static_cast<uint32_t>(st) > MOLDTEX_ERROR_BUSY) bug("unknown status");
  if (st != MOLDTEX_OK && moldtex_last_error()[0] == '\0') bug("a failure without a message");
  return st;
}

std::string temp_path(const char* name) {
  return "/tmp/moldtex_fuzz_" + std::to_string(getpid()) + "_" + name;
}

moldtex_surface_point point(Bytes& in) {
  moldtex_surface_point p;
  p.triangle = in.u8();
  for (float& b : p.bary) b = in.f32();
  return p;
}

moldtex_brush brush(Bytes& in) {
  moldtex_brush b;
  moldtex_brush_init(&b);
  b.center = point(in);
  b.radius = in.f32();
  b.strength = in.f32();
  b.falloff = in.f32();
  b.mode = in.u8() % 3;
  b.channel = in.u8() % 5;
  b.value = in.f32();
  if (std::getenv("MOLDTEX_FUZZ_TRACE"))
    std::fprintf(stderr, "brush: triangle %u (%g %g %g), radius %g, strength %g, falloff %g\n", b.center.triangle,
                 b.center.bary[0], b.center.bary[1], b.center.bary[2], b.radius, b.strength, b.falloff);
  return b;
}

// The simulation's pheromone after accepted calls: finite, in [0, 1].
// MoMaS pheromone lies in [0, 1]; the continuous model's u / U is finite and >= 0.
void check_pheromone(moldtex_sim sim, uint32_t width, uint32_t height) {
  std::vector<float> rgba(size_t(width) * height * 4);
  if (check(moldtex_sim_read_rgba(sim, rgba.data(), rgba.size())) != MOLDTEX_OK) bug("read_rgba failed");
  moldtex_sim_config c;
  moldtex_sim_config_init(&c);
  if (check(moldtex_sim_get_config(sim, &c)) != MOLDTEX_OK) bug("get_config failed");
  // Gray-Scott's U and V: finite and >= 0 (V may pass 1 a little).
  const bool continuous = c.model == MOLDTEX_MODEL_CONTINUOUS || c.model == MOLDTEX_MODEL_GRAY_SCOTT;
  static const bool trace = std::getenv("MOLDTEX_FUZZ_TRACE") != nullptr;
  if (trace)
    for (size_t i = 0; i < rgba.size(); ++i)
      if (!(rgba[i] >= 0.f && std::isfinite(rgba[i]))) std::fprintf(stderr, "  texel %zu channel %zu: %g\n", i / 4, i % 4, rgba[i]);
  for (float v : rgba)
    if (!(v >= 0.f && (continuous ? std::isfinite(v) : v <= 1.f)))
      bug(continuous ? "a concentration that is negative or not finite" : "a pheromone value outside [0, 1]");
  // The intrinsic domain's own vertex values, which the texture only shows interpolated
  // (and which a checkpoint saves): finite and >= 0 too.
  if (c.domain != MOLDTEX_DOMAIN_INTRINSIC) return;
  moldtex_domain_info d;
  moldtex_domain_info_init(&d);
  if (check(moldtex_sim_get_domain_info(sim, &d)) != MOLDTEX_OK) bug("get_domain_info failed");
  std::vector<float> values(size_t(d.cell_count) * 4);  // (up to 4 planes)
  if (check(moldtex_sim_read_intrinsic_vertices(sim, nullptr, values.data(), d.cell_count)) != MOLDTEX_OK)
    bug("read_intrinsic_vertices failed");
  for (float v : values)
    if (!(v >= 0.f && std::isfinite(v))) bug("an intrinsic vertex value that is negative or not finite");
}

enum Op : uint8_t {
  kRayCast, kClosestPoint, kTrace, kPaint, kCreateSim, kStep, kAddAgents, kEraseAgents, kUndo,
  kSetFood, kSetFields, kCheckpoint, kRasterize, kSetParams, kReset, kSetContinuous, kSetBias, kSetMap,
  kSurfaceMap, kColourRamp, kSetReaction, kIntrinsic, kOpCount
};

void fuzz_mesh(Bytes& in) {
  const uint32_t nv = in.u8() % 24, nt = in.u8() % 24;
  const uint8_t flags = in.u8();
  const bool indexed = flags & 1;
  std::vector<float> positions(3 * nv);
  for (float& p : positions) p = (flags & 2) ? in.f32() : static_cast<float>(in.u8() % 16) * 0.25f;
  std::vector<uint32_t> triangles(3 * nt);
  for (uint32_t& t : triangles) t = in.u8() % (nv + 1);  // nv: one index out of range
  const uint32_t uv_count = indexed ? nv : 3 * nt;
  std::vector<float> uvs(2 * uv_count);
  for (float& u : uvs) u = (flags & 4) ? in.f32() : static_cast<float>(in.u8() % 16) / 8.f - 0.25f;
  moldtex_mesh_desc d;
  moldtex_mesh_desc_init(&d);
  d.positions = positions.data();
  d.vertex_count = nv;
  d.triangles = triangles.data();
  d.triangle_count = nt;
  // flags & 8: a mesh without UVs (placeholder layout; the intrinsic domain runs on it).
  const bool no_uvs = flags & 8;
  d.uvs = no_uvs ? nullptr : uvs.data();
  d.uv_count = no_uvs ? 0 : uv_count;
  d.triangle_uvs = indexed && !no_uvs ? triangles.data() : nullptr;
  moldtex_surface surface = nullptr;
  if (check(moldtex_surface_create(&d, &surface)) != MOLDTEX_OK) {
    if (surface) bug("a failed create handed out a surface");
    return;
  }
  moldtex_surface_info info;
  moldtex_surface_info_init(&info);
  check(moldtex_surface_get_info(surface, &info));

  moldtex_sim sim = nullptr;
  uint32_t width = 0, height = 0;
  // A walk may cross up to 4096 edges (MTX_MAX_CROSSINGS_PER_WALK), as on a long sliver
  // under texels larger than the mesh; few agents and steps keep such inputs within the
  // time limit under the sanitizers' instrumentation.
  uint32_t step_budget = 6;
  static const bool trace = std::getenv("MOLDTEX_FUZZ_TRACE") != nullptr;
  if (trace) std::fprintf(stderr, "surface: area %g, UV area %g\n", info.area, info.uv_area);
  // MOLDTEX_FUZZ_TRACE=1 prints each operation (to see what a slow or crashing input does).
  if (trace) {
    std::fprintf(stderr, "mesh: %u vertices, %u triangles, flags %u\n", nv, nt, flags);
    for (uint32_t v = 0; v < nv; ++v)
      std::fprintf(stderr, "  v%u (%.9g %.9g %.9g)\n", v, positions[3 * v], positions[3 * v + 1], positions[3 * v + 2]);
    for (uint32_t t = 0; t < nt; ++t)
      std::fprintf(stderr, "  t%u (%u %u %u)\n", t, triangles[3 * t], triangles[3 * t + 1], triangles[3 * t + 2]);
    for (uint32_t u = 0; u < uv_count; ++u) std::fprintf(stderr, "  uv%u (%.9g %.9g)\n", u, uvs[2 * u], uvs[2 * u + 1]);
  }
  for (int n = 0; n < 24 && !in.empty(); ++n) {
    const uint8_t op = in.u8() % kOpCount;
    if (trace) std::fprintf(stderr, "op %u at byte %zu\n", op, in.at);
    switch (op) {
      case kRayCast: {
        float o[3], dir[3];
        for (float& v : o) v = in.f32();
        for (float& v : dir) v = in.f32();
        moldtex_ray_hit hit;
        moldtex_ray_hit_init(&hit);
        const float max_distance = in.f32();
        if (check(moldtex_surface_ray_cast(surface, o, dir, max_distance, &hit)) == MOLDTEX_OK && hit.hit &&
            (!(hit.distance >= 0.f && hit.distance <= max_distance) || hit.point.triangle >= info.triangle_count)) {
          std::fprintf(stderr, "ray (%g %g %g) + s (%g %g %g), s <= %g: hit at s = %g on triangle %u\n", o[0],
                       o[1], o[2], dir[0], dir[1], dir[2], max_distance, hit.distance, hit.point.triangle);
          bug("a ray hit outside [0, max_distance] or on a bad triangle");
        }
        break;
      }
      case kClosestPoint: {
        float p[3];
        for (float& v : p) v = in.f32();
        moldtex_surface_point q;
        float distance = -1;
        if (check(moldtex_surface_closest_point(surface, p, &q, &distance)) == MOLDTEX_OK &&
            (q.triangle >= info.triangle_count || !(distance >= 0.f)))
          bug("a closest point with a bad triangle or distance");
        break;
      }
      case kTrace: {
        const moldtex_surface_point start = point(in);
        float dir[3];
        for (float& v : dir) v = in.f32();
        const float length = in.f32();
        moldtex_surface_point end;
        float path[3 * 8];
        uint32_t count = 0;
        float xyz[3], uv[2];
        check(moldtex_surface_evaluate(surface, &start, xyz, uv));
        if (check(moldtex_surface_trace(surface, &start, dir, length, &end, path, 8, &count)) == MOLDTEX_OK &&
            end.triangle >= info.triangle_count)
          bug("a trace ended on a bad triangle");
        break;
      }
      case kPaint: {
        const uint32_t w = 1 + in.u8() % 64, h = 1 + in.u8() % 64;
        const moldtex_brush b = brush(in);
        std::vector<float> img(size_t(w) * h * 4, 0.f);
        uint32_t changed = 0;
        check(moldtex_surface_paint(surface, w, h, img.data(), img.size(), &b, &changed));
        break;
      }
      case kCreateSim: {
        if (sim) break;
        moldtex_sim_config c;
        moldtex_sim_config_init(&c);
        c.width = 8 + in.u8() % 25;
        c.height = 8 + in.u8() % 25;
        c.agent_count = 1 + in.u16() % 64;
        c.seed = in.u8();
        c.backend = MOLDTEX_BACKEND_CPU;  // OpenCL (PoCL's JIT) is not fuzzed under ASan
        c.species_count = 1 + in.u8() % 4;
        c.seed_shape = in.u8() % 6;
        c.seed_center = point(in);
        c.seed_radius = in.f32();
        c.seed_rays = in.u16() % 1100;
        c.model = in.u8() % 4;  // 3 is not a model
        // The domain from bits the inputs already hold (the corpus keeps its meaning):
        // the seed's top bit; its next bit gives the bound the seed radius (any float).
        c.domain = (c.seed & 0x80) ? MOLDTEX_DOMAIN_INTRINSIC : MOLDTEX_DOMAIN_TEXTURE;
        c.intrinsic_bound = (c.seed & 0x40) ? c.seed_radius : 0.f;
        moldtex_sim_params p;
        moldtex_sim_params_init(&p);
        p.thread_count = 1;
        if (trace)
          std::fprintf(stderr, "sim: %u x %u, %u agents, %u species, shape %u, radius %g, model %u, domain %u, bound %g\n",
                       c.width, c.height, c.agent_count, c.species_count, c.seed_shape, c.seed_radius, c.model,
                       c.domain, c.intrinsic_bound);
        if (check(moldtex_sim_create(surface, &c, &p, &sim)) == MOLDTEX_OK) {
          width = c.width;
          height = c.height;
          check_pheromone(sim, width, height);
        } else if (sim) {
          bug("a failed create handed out a simulation");
        }
        break;
      }
      case kStep: {
        const uint32_t steps = std::min<uint32_t>(in.u8() % 4, step_budget);
        step_budget -= steps;
        if (trace && sim) {
          moldtex_sim_params p;
          moldtex_sim_params_init(&p);
          moldtex_sim_get_params(sim, &p);
          std::fprintf(stderr, "step %u: speed %g, vision %g, substeps %u\n", steps, p.movement_speed,
                       p.vision_distance, p.substeps);
        }
        if (sim && check(moldtex_sim_step(sim, steps)) == MOLDTEX_OK) {
          check_pheromone(sim, width, height);
          // The result per mesh vertex (intrinsic domain; the texture domain refuses).
          std::vector<float> per_vertex(4ull * info.vertex_count + 1);
          if (check(moldtex_sim_read_vertex_rgba(sim, per_vertex.data(), per_vertex.size())) == MOLDTEX_OK)
            for (float v : per_vertex)
              if (!(v >= 0.f && std::isfinite(v))) bug("a vertex colour that is negative or not finite");
        }
        break;
      }
      case kAddAgents: {
        const moldtex_brush b = brush(in);
        const uint32_t count = in.u16() % 64, batch = in.u16() % 4;
        if (sim && check(moldtex_sim_add_agents(sim, &b, count, batch)) == MOLDTEX_OK)
          check_pheromone(sim, width, height);
        break;
      }
      case kEraseAgents: {
        const moldtex_brush b = brush(in);
        const uint32_t batch = in.u16() % 4;
        uint32_t removed = 0;
        if (sim && check(moldtex_sim_erase_agents(sim, &b, batch, &removed)) == MOLDTEX_OK)
          check_pheromone(sim, width, height);  // (Gray-Scott: the dab paints)
        break;
      }
      case kUndo: {
        const uint32_t batch = in.u16() % 4;
        if (sim && check(moldtex_sim_undo_agents(sim, batch)) == MOLDTEX_OK) check_pheromone(sim, width, height);
        break;
      }
      case kSetFood: {
        moldtex_food_source food[5];
        const uint32_t count = in.u8() % 6;
        for (uint32_t j = 0; j < count; ++j) {
          for (float& v : food[j].position) v = in.f32();
          food[j].strength = in.f32();
          food[j].amount = in.f32();
        }
        if (sim) check(moldtex_sim_set_food(sim, food, count));
        break;
      }
      case kSetFields: {
        float pattern[8];
        for (float& v : pattern) v = in.f32();
        if (!sim) break;
        std::vector<float> fields(size_t(width) * height * 4);
        for (size_t i = 0; i < fields.size(); ++i) fields[i] = pattern[i % 8];
        check(moldtex_sim_set_fields(sim, fields.data(), fields.size()));
        break;
      }
      case kCheckpoint: {
        if (!sim) break;
        const std::string path = temp_path("roundtrip.bin");
        if (check(moldtex_sim_save_checkpoint(sim, path.c_str())) == MOLDTEX_OK &&
            check(moldtex_sim_load_checkpoint(sim, path.c_str())) != MOLDTEX_OK)
          bug("a checkpoint just saved did not load");
        std::remove(path.c_str());
        break;
      }
      case kRasterize: {
        const uint32_t w = 8 + in.u8() % 24, h = 8 + in.u8() % 24;
        std::vector<float> corners(size_t(info.triangle_count) * 12);
        for (size_t i = 0; i < corners.size(); ++i) corners[i] = i < 8 ? in.f32() : 0.5f;
        std::vector<float> out(size_t(w) * h * 4);
        check(moldtex_surface_rasterize_corners(surface, w, h, corners.data(), corners.size(), out.data(),
                                                out.size()));
        break;
      }
      case kSetParams: {
        moldtex_sim_params p;
        moldtex_sim_params_init(&p);
        const uint8_t which = in.u8();
        float* fields[] = {&p.movement_speed, &p.turn_speed, &p.vision_distance, &p.vision_angle,
                           &p.evaporation_rate, &p.diffusion_rate, &p.deposit, &p.time_step,
                           &p.hunger_rate, &p.food_radius};
        *fields[which % 10] = in.f32();
        p.substeps = in.u8() % 70;
        p.sensor_size = in.u8() % 6;
        p.thread_count = 1;
        if (trace) std::fprintf(stderr, "params: field %u = %g, substeps %u\n", which % 10, *fields[which % 10], p.substeps);
        if (sim) check(moldtex_sim_set_params(sim, &p));
        moldtex_species_params sp;
        moldtex_species_params_init(&sp, which % 4);
        sp.attraction[which % 4] = in.f32();
        if (sim) check(moldtex_sim_set_species_params(sim, which % 5, &sp));
        break;
      }
      case kSetContinuous: {
        moldtex_continuous_params p;
        moldtex_continuous_params_init(&p);
        float* fields[] = {&p.move_rate, &p.turn_rate, &p.turn_frequency, &p.sensor_distance,
                           &p.sensor_angle, &p.deposit_rate, &p.diffusion_rate, &p.decay_rate,
                           &p.mean_lifetime, &p.activation_time, &p.time_step, &p.bias_strength};
        const uint8_t which = in.u8();
        *fields[which % 12] = in.f32();
        p.bias_symmetry = in.u8() % 8;
        p.bias_spawn = in.u8() % 3;
        p.integrator = in.u8() % 4;
        if (sim) check(moldtex_sim_set_continuous_params(sim, &p));
        break;
      }
      case kSetReaction: {
        moldtex_reaction_params p;
        moldtex_reaction_params_init(&p);
        float* fields[] = {&p.feed, &p.kill, &p.diffusion_u, &p.diffusion_v, &p.time_step, &p.seed_radius};
        *fields[in.u8() % 6] = in.f32();
        p.seed_count = in.u16() % 1100;
        if (trace)
          std::fprintf(stderr, "reaction: F %g k %g Du %g Dv %g dt %g seeds %u radius %g\n", p.feed, p.kill,
                       p.diffusion_u, p.diffusion_v, p.time_step, p.seed_count, p.seed_radius);
        if (sim) check(moldtex_sim_set_reaction_params(sim, &p));
        break;
      }
      case kSetBias: {
        float pattern[6];
        for (float& v : pattern) v = in.f32();
        if (!sim) break;
        const uint8_t how = in.u8() % 3;  // 0: clear, 1: right size, 2: one short
        std::vector<float> bias(size_t(info.triangle_count) * 3 - (how == 2 && info.triangle_count ? 1 : 0));
        for (size_t i = 0; i < bias.size(); ++i) bias[i] = pattern[i % 6];
        check(moldtex_sim_set_bias(sim, how == 0 ? nullptr : bias.data(), bias.size()));
        break;
      }
      case kSurfaceMap: {
        // One of the four map tools (issue 12) on values from the bytes: a repeating
        // pattern of 4 floats (NaN and huge ones get refused), a fixed mask from a byte,
        // a count that is sometimes one short. Accepted calls must give finite outputs.
        const uint8_t which = in.u8();
        float pattern[4];
        for (float& v : pattern) v = in.f32();
        const float scalar = in.f32();
        const uint8_t mask_bits = in.u8();
        const size_t n = info.vertex_count - ((which & 4) && info.vertex_count ? 1 : 0);
        std::vector<float> values(n);
        std::vector<uint8_t> fixed(n);
        for (size_t i = 0; i < n; ++i) {
          values[i] = pattern[i % 4];
          fixed[i] = (mask_bits >> (i % 8)) & 1;
        }
        std::vector<float> out(std::max<size_t>(info.vertex_count, 3 * size_t(info.triangle_count)), 0.f);
        moldtex_status st = MOLDTEX_OK;
        switch (which % 4) {
          case 0: st = check(moldtex_surface_geodesic_distance(surface, values.data(), n, scalar, out.data(), out.size())); break;
          case 1: st = check(moldtex_surface_laplace_interpolate(surface, values.data(), fixed.data(), n, out.data(), out.size())); break;
          case 2: st = check(moldtex_surface_diffuse_map(surface, values.data(), n, scalar, out.data(), out.size())); break;
          default: st = check(moldtex_surface_map_gradient(surface, values.data(), n, out.data(), out.size())); break;
        }
        if (st == MOLDTEX_OK)
          for (float v : out)
            if (!std::isfinite(v)) bug("a surface map tool gave a non-finite value");
        if (st == MOLDTEX_OK && which % 4 == 0)
          for (size_t i = 0; i < info.vertex_count; ++i)
            if (out[i] < 0.f && out[i] != -1.f) bug("a negative geodesic distance other than -1 (unreachable)");
        break;
      }
      case kIntrinsic: {
        // Intrinsic Delaunay triangulation (issue 11) with a bound from the bytes: raw (NaN,
        // negative and tiny ones get refused) or area / bound^2 = 1..2000, and at most 4000
        // insertions (about 30 ms in Release), so one op stays under 0.1 s. Then a few points (raw weights, or
        // made valid) located and mapped back: accepted results are valid points.
        const uint8_t how = in.u8();
        const float raw = in.f32();
        const uint16_t target = in.u16();
        moldtex_intrinsic_params ip;
        moldtex_intrinsic_params_init(&ip);
        ip.max_insertions = 2 * (1 + target % 2000);
        ip.max_circumradius =
            (how & 1) ? raw : (how & 2) ? 0.f : static_cast<float>(std::sqrt(info.area / (1 + target % 2000)));
        if (how & 4) ip.struct_size = how & 8 ? 4 : 0;  // refused: initialise with _init
        // The points are read first, so the bytes after this op do not depend on the outcome.
        const uint32_t k = 1 + in.u8() % 4;
        std::vector<moldtex_surface_point> pts(k), loc(k), back(k);
        for (auto& q : pts) {
          q = point(in);
          if (how & 16) {  // made valid
            q.triangle %= info.triangle_count;
            float sum = 0;
            for (float& b : q.bary) sum += (b = std::isfinite(b) ? std::fabs(std::fmod(b, 8.f)) : 1.f);
            for (float& b : q.bary) b = sum > 0 ? b / sum : 1.f / 3;
          }
        }
        moldtex_intrinsic intr = nullptr;
        if (check(moldtex_intrinsic_create(surface, &ip, &intr)) != MOLDTEX_OK) {
          if (intr) bug("a failed intrinsic_create handed out a handle");
          break;
        }
        moldtex_intrinsic_info ii;
        moldtex_intrinsic_info_init(&ii);
        if (check(moldtex_intrinsic_get_info(intr, &ii)) != MOLDTEX_OK) bug("intrinsic_get_info failed");
        if (trace)
          std::fprintf(stderr, "intrinsic: bound %g, %u vertices, %u triangles, %s\n", ip.max_circumradius,
                       ii.vertex_count, ii.triangle_count, ii.message);
        if (ii.vertex_count < ii.input_vertex_count || ii.input_vertex_count != info.vertex_count ||
            ii.insertions + ii.boundary_splits > ip.max_insertions ||
            ii.vertex_count != ii.input_vertex_count + ii.insertions + ii.boundary_splits)
          bug("intrinsic counts are inconsistent");
        if (int64_t(ii.triangle_count) * 3 > int64_t(ii.edge_count) * 2 || ii.triangle_count == 0 ||
            !std::isfinite(ii.area) || !(ii.area > 0) || !std::isfinite(ii.largest_circumradius))
          bug("intrinsic triangulation with impossible counts or geometry");
        std::vector<moldtex_surface_point> vp(ii.vertex_count);
        if (check(moldtex_intrinsic_vertex_points(intr, vp.data(), ii.vertex_count)) != MOLDTEX_OK)
          bug("intrinsic_vertex_points failed");
        auto valid = [](const moldtex_surface_point& q, uint32_t triangles) {
          double sum = 0;
          for (float b : q.bary) {
            if (!std::isfinite(b) || b < 0.f) return false;
            sum += b;
          }
          return q.triangle < triangles && std::fabs(sum - 1.0) < 1e-4;
        };
        for (const auto& q : vp)
          if (q.triangle != MOLDTEX_INTRINSIC_NO_TRIANGLE && !valid(q, info.triangle_count))
            bug("an intrinsic vertex's input point is not a valid surface point");
        if (check(moldtex_intrinsic_locate(intr, pts.data(), k, loc.data())) == MOLDTEX_OK) {
          for (const auto& q : loc)
            if (!valid(q, ii.triangle_count)) bug("intrinsic_locate gave an invalid intrinsic point");
          if (check(moldtex_intrinsic_to_input(intr, loc.data(), k, back.data())) != MOLDTEX_OK)
            bug("intrinsic_to_input refused a point that locate gave");
          for (const auto& q : back)
            if (!valid(q, info.triangle_count)) bug("intrinsic_to_input gave an invalid input point");
        }
        moldtex_intrinsic_release(intr);
        break;
      }
      case kColourRamp: {
        // Colour map from up to 64 pixels of 3 or 4 channels from the bytes (NaN and huge
        // ones get refused) with options from the bytes; an accepted call gives 2..max_stops
        // increasing stops in [0, 1] with finite, non-negative colours.
        const uint8_t shape = in.u8();
        const uint32_t channels = (shape & 1) ? 4u : 3u;
        const size_t count = in.u8() % 65;
        std::vector<float> pixels(count * channels);
        for (float& v : pixels) v = (shape & 2) ? in.f32() : static_cast<float>(in.u8()) / 200.f;
        moldtex_colour_ramp_desc d;
        moldtex_colour_ramp_desc_init(&d);
        d.channels = (shape & 4) ? in.u8() % 6 : channels;  // sometimes wrong
        d.srgb_encoded = (shape >> 3) & 1;
        d.reverse = (shape >> 4) & 1;
        d.sample_count = 12 + in.u8() % 64;  // (below 16: refused)
        d.neighbour_count = in.u8() % 70;
        d.max_stops = in.u8() % 36;
        d.tolerance = (shape & 32) ? in.f32() : 1.f;
        d.peak_position = (shape & 64) ? in.f32() : -1.f;
        moldtex_colour_stop stops[32];
        moldtex_colour_ramp_info ramp_info;
        moldtex_colour_ramp_info_init(&ramp_info);
        // The pixel count the buffer holds at the declared channel count (the API cannot see
        // a buffer's size: a caller that declares more channels than it has is its bug).
        const size_t declared = d.channels ? pixels.size() / d.channels : count;
        if (check(moldtex_colour_ramp_from_pixels(pixels.data(), declared, &d, stops, 32, &ramp_info)) == MOLDTEX_OK) {
          if (ramp_info.stop_count < 2 || ramp_info.stop_count > d.max_stops) bug("a colour map with a wrong stop count");
          for (uint32_t i = 0; i < ramp_info.stop_count; ++i) {
            if (!(stops[i].position >= 0.f && stops[i].position <= 1.f) ||
                (i > 0 && !(stops[i].position > stops[i - 1].position)))
              bug("colour map stops out of [0, 1] or not increasing");
            for (float c : stops[i].color)
              if (!std::isfinite(c) || c < 0.f) bug("a colour map stop with a non-finite or negative colour");
          }
          if (!(ramp_info.explained >= 0.f && ramp_info.explained <= 1.f)) bug("explained outside [0, 1]");
        }
        break;
      }
      case kReset:
        if (sim && check(moldtex_sim_reset(sim)) == MOLDTEX_OK) check_pheromone(sim, width, height);
        break;
      case kSetMap: {
        // A parameter map or stimulus: two values in a checkerboard of 4-texel squares, or
        // cleared, or one value short; then read back.
        const uint32_t kind = in.u8() % (MOLDTEX_MAP_COUNT + 1);  // COUNT is not a map
        const float a = in.f32(), b = in.f32();
        const uint8_t how = in.u8() % 3;  // 0: clear, 1: right size, 2: one short
        if (trace) std::fprintf(stderr, "map %u: %g / %g, how %u\n", kind, a, b, how);
        if (!sim) break;
        std::vector<float> map(size_t(width) * height - (how == 2 ? 1 : 0));
        for (size_t i = 0; i < map.size(); ++i) map[i] = ((i % width) / 4 + (i / width) / 4) % 2 ? a : b;
        if (check(moldtex_sim_set_map(sim, kind, how == 0 ? nullptr : map.data(), map.size())) == MOLDTEX_OK) {
          std::vector<float> back(size_t(width) * height);
          uint32_t set = 0;
          if (check(moldtex_sim_get_map(sim, kind, back.data(), back.size(), &set)) != MOLDTEX_OK ||
              set != (how == 0 ? 0u : 1u))
            bug("a map just set did not read back");
        }
        break;
      }
      default:
        break;
    }
  }
  if (sim) {
    moldtex_sim_stats st;
    moldtex_sim_stats_init(&st);
    check(moldtex_sim_get_stats(sim, &st));
    if (!std::isfinite(st.coverage) || !std::isfinite(st.presence)) {
      std::fprintf(stderr, "coverage %g, presence %g, U %g, mean %g\n", st.coverage, st.presence, st.u_metric,
                   st.mean_concentration);
      bug("non-finite statistics");
    }
  }
  moldtex_sim_release(sim);
  moldtex_surface_release(surface);
}

// A small valid simulation's checkpoint, patched: (offset, length, bytes) runs, then an
// optional truncation. A checkpoint that loads must leave the simulation usable.
void fuzz_checkpoint(Bytes& in) {
  static const float kPositions[] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};
  static const uint32_t kTriangles[] = {0, 1, 2, 0, 2, 3};
  static const float kUvs[] = {0, 0, 1, 0, 1, 1, 0, 1};
  moldtex_mesh_desc d;
  moldtex_mesh_desc_init(&d);
  d.positions = kPositions;
  d.vertex_count = 4;
  d.triangles = kTriangles;
  d.triangle_count = 2;
  d.uvs = kUvs;
  d.uv_count = 4;
  d.triangle_uvs = kTriangles;
  moldtex_surface surface = nullptr;
  if (moldtex_surface_create(&d, &surface) != MOLDTEX_OK) bug("the fixed quad was refused");
  moldtex_sim_config c;
  moldtex_sim_config_init(&c);
  c.width = c.height = 16;
  c.agent_count = 40;
  c.backend = MOLDTEX_BACKEND_CPU;
  c.species_count = 2;
  moldtex_sim_params p;
  moldtex_sim_params_init(&p);
  p.thread_count = 1;
  p.hunger_rate = 0.5f;
  moldtex_sim sim = nullptr;
  if (moldtex_sim_create(surface, &c, &p, &sim) != MOLDTEX_OK) bug("the fixed simulation was refused");
  const moldtex_food_source food = {{0.5f, 0.5f, 0.f}, 1.f, 10.f};
  moldtex_sim_set_food(sim, &food, 1);
  moldtex_sim_step(sim, 3);
  const std::string path = temp_path("patched.bin");
  if (moldtex_sim_save_checkpoint(sim, path.c_str()) != MOLDTEX_OK) bug("could not save the checkpoint");
  std::vector<char> bytes;
  {
    std::ifstream file(path, std::ios::binary);
    bytes.assign(std::istreambuf_iterator<char>(file), std::istreambuf_iterator<char>());
  }
  const uint8_t runs = in.u8() % 8;
  for (uint8_t r = 0; r < runs && !bytes.empty(); ++r) {
    size_t at = in.u16() % bytes.size();
    const uint8_t length = 1 + in.u8() % 16;
    for (uint8_t k = 0; k < length && at < bytes.size(); ++k) bytes[at++] = static_cast<char>(in.u8());
  }
  if (in.u8() & 1) bytes.resize(in.u16() % (bytes.size() + 1));
  {
    std::ofstream file(path, std::ios::binary | std::ios::trunc);
    file.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  }
  moldtex_sim other = nullptr;
  if (moldtex_sim_create(surface, &c, &p, &other) != MOLDTEX_OK) bug("the fixed simulation was refused");
  if (check(moldtex_sim_load_checkpoint(other, path.c_str())) == MOLDTEX_OK) {
    check_pheromone(other, 16, 16);
    check(moldtex_sim_step(other, 2));
    check_pheromone(other, 16, 16);
  }
  std::remove(path.c_str());
  moldtex_sim_release(other);
  moldtex_sim_release(sim);
  moldtex_surface_release(surface);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  Bytes in{data, size};
  if (in.u8() & 1)
    fuzz_checkpoint(in);
  else
    fuzz_mesh(in);
  return 0;
}
