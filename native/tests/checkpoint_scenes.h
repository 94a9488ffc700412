// checkpoint_scenes.h — the simulations whose checkpoints are kept as fixtures
// (native/tests/data/checkpoints/v<format>/<scene>.ckpt), so that every later version is
// tested on loading the files an earlier one wrote (test_checkpoint_compat.cpp).
//
// Each scene sets values that differ from every default (parameters, species, fields,
// food, bias, maps), so a loader that drops or shifts one is seen. The fixture writer
// (make_checkpoint_fixtures.cpp) and the test build the same scene from this header.
#ifndef MOLDTEX_TESTS_CHECKPOINT_SCENES_H
#define MOLDTEX_TESTS_CHECKPOINT_SCENES_H

#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "mesh_fixtures.h"

namespace mtx {

struct CheckpointScene {
  std::string name;
  Mesh mesh;
  moldtex_sim_config config;
  moldtex_sim_params params;
  // Applied after create (parameters, fields, food, bias, maps); MOLDTEX_OK or the failure.
  moldtex_status (*settle)(moldtex_sim sim, const CheckpointScene& scene);
  uint32_t frames;           // frames of the bake that writes the checkpoint (metrics rows)
  uint32_t steps_per_frame;  //
};

// The distinctive values each scene sets, also what the test expects back.
inline moldtex_species_params SceneSpecies(uint32_t k) {
  moldtex_species_params s;
  moldtex_species_params_init(&s, k);
  s.movement_speed = 1.25f + 0.25f * k;
  s.turn_speed = 21.f + k;
  s.vision_distance = 1.5f + 0.125f * k;
  s.vision_angle = 33.f - k;
  s.deposit = 0.75f - 0.0625f * k;
  for (uint32_t j = 0; j < MOLDTEX_MAX_SPECIES; ++j) s.attraction[j] = j == k ? 0.875f : -0.375f;
  return s;
}

inline std::vector<moldtex_food_source> SceneFood() {
  return {{{0.f, 0.f, 1.f}, 2.5f, 400.f}, {{1.f, 0.f, 0.f}, 1.5f, -1.f}};
}

inline moldtex_continuous_params SceneContinuous() {
  moldtex_continuous_params p;
  moldtex_continuous_params_init(&p);
  p.move_rate *= 1.125f;
  p.turn_rate *= 0.875f;
  p.sensor_distance *= 1.25f;
  p.deposit_rate *= 1.5f;
  p.decay_rate *= 0.75f;
  p.mean_lifetime = 7.5f;
  p.bias_strength = 0.5f;
  p.bias_symmetry = 2;
  return p;
}

inline moldtex_reaction_params SceneReaction() {
  moldtex_reaction_params p;
  moldtex_reaction_params_init(&p);
  p.feed *= 1.0625f;
  p.kill *= 0.96875f;
  return p;
}

// A map over `texels` image texels: a smooth ramp in [lo, hi].
inline std::vector<float> SceneMap(size_t width, size_t height, float lo, float hi) {
  std::vector<float> m(width * height);
  for (size_t y = 0; y < height; ++y)
    for (size_t x = 0; x < width; ++x) m[y * width + x] = lo + (hi - lo) * float(x + y) / float(width + height - 2);
  return m;
}

// Fields: spawn weight 1 everywhere, an obstacle square, an attractor stripe.
inline std::vector<float> SceneFields(size_t width, size_t height) {
  std::vector<float> f(width * height * 4, 0.f);
  for (size_t y = 0; y < height; ++y)
    for (size_t x = 0; x < width; ++x) {
      float* t = f.data() + 4 * (y * width + x);
      t[0] = 1.f;
      t[1] = (x > width / 4 && x < width / 3 && y > height / 4 && y < height / 3) ? 1.f : 0.f;
      t[2] = (y * 8 / height == 5) ? 0.625f : 0.f;
    }
  return f;
}

inline std::vector<CheckpointScene> CheckpointScenes() {
  std::vector<CheckpointScene> scenes;
  moldtex_sim_params p = default_params();
  p.thread_count = 2;
  {  // MoMaS: three species, fields, food, surface units, detail 2
    CheckpointScene s{"momas", make_uv_sphere(16, 8, 1.0), make_config(32, 32, 600, 11), p, nullptr, 3, 4};
    s.config.seed = 11;  // (not shifted by MOLDTEX_TEST_SEED_OFFSET: the file holds it)
    s.config.species_count = 3;
    s.config.detail = 2;
    s.params.length_unit = 0.06f;
    s.params.evaporation_rate = 0.375f;
    s.params.diffusion_rate = 2.5f;
    s.params.hunger_rate = 0.25f;
    s.params.food_radius = 0.3f;
    s.params.sensor_size = 1;
    s.settle = [](moldtex_sim sim, const CheckpointScene& sc) {
      for (uint32_t k = 0; k < sc.config.species_count; ++k) {
        const moldtex_species_params sp = SceneSpecies(k);
        if (moldtex_sim_set_species_params(sim, k, &sp) != MOLDTEX_OK) return MOLDTEX_ERROR_INTERNAL;
      }
      const std::vector<float> fields = SceneFields(sc.config.width, sc.config.height);
      const std::vector<moldtex_food_source> food = SceneFood();
      if (moldtex_sim_set_fields(sim, fields.data(), fields.size()) != MOLDTEX_OK) return MOLDTEX_ERROR_INTERNAL;
      return moldtex_sim_set_food(sim, food.data(), uint32_t(food.size()));
    };
    scenes.push_back(s);
  }
  {  // Continuous on the texture domain: its parameters, a bias, a lifetime map
    CheckpointScene s{"continuous", make_torus(24, 12, 1.0, 0.35), make_config(32, 32, 500, 12), p, nullptr, 2, 5};
    s.config.seed = 12;  // (not shifted by MOLDTEX_TEST_SEED_OFFSET: the file holds it)
    s.config.model = MOLDTEX_MODEL_CONTINUOUS;
    s.settle = [](moldtex_sim sim, const CheckpointScene& sc) {
      const moldtex_continuous_params cp = SceneContinuous();
      if (moldtex_sim_set_continuous_params(sim, &cp) != MOLDTEX_OK) return MOLDTEX_ERROR_INTERNAL;
      std::vector<float> bias(3 * size_t(sc.mesh.triangle_count()));
      for (size_t t = 0; t < bias.size() / 3; ++t) {
        const Vec3 c = sc.mesh.corner(uint32_t(t), 0);
        bias[3 * t] = float(-c[1]);
        bias[3 * t + 1] = float(c[0]);
        bias[3 * t + 2] = 0.25f;
      }
      if (moldtex_sim_set_bias(sim, bias.data(), bias.size()) != MOLDTEX_OK) return MOLDTEX_ERROR_INTERNAL;
      const std::vector<float> lifetime = SceneMap(sc.config.width, sc.config.height, 0.5f, 1.5f);
      return moldtex_sim_set_map(sim, MOLDTEX_MAP_MEAN_LIFETIME, lifetime.data(), lifetime.size());
    };
    scenes.push_back(s);
  }
  {  // Continuous on the intrinsic domain (vertex values beside the texture)
    CheckpointScene s{"intrinsic", make_uv_sphere(16, 8, 1.0), make_config(32, 32, 400, 13), p, nullptr, 2, 5};
    s.config.seed = 13;  // (not shifted by MOLDTEX_TEST_SEED_OFFSET: the file holds it)
    s.config.model = MOLDTEX_MODEL_CONTINUOUS;
    s.config.domain = MOLDTEX_DOMAIN_INTRINSIC;
    s.settle = [](moldtex_sim sim, const CheckpointScene&) {
      const moldtex_continuous_params cp = SceneContinuous();
      return moldtex_sim_set_continuous_params(sim, &cp);
    };
    scenes.push_back(s);
  }
  {  // Gray-Scott: its parameters and a feed map
    CheckpointScene s{"gray_scott", make_uv_sphere(16, 8, 1.0), make_config(32, 32, 1, 14), p, nullptr, 2, 6};
    s.config.seed = 14;  // (not shifted by MOLDTEX_TEST_SEED_OFFSET: the file holds it)
    s.config.model = MOLDTEX_MODEL_GRAY_SCOTT;
    s.settle = [](moldtex_sim sim, const CheckpointScene& sc) {
      const moldtex_reaction_params rp = SceneReaction();
      if (moldtex_sim_set_reaction_params(sim, &rp) != MOLDTEX_OK) return MOLDTEX_ERROR_INTERNAL;
      const std::vector<float> feed = SceneMap(sc.config.width, sc.config.height, 0.75f, 1.25f);
      return moldtex_sim_set_map(sim, MOLDTEX_MAP_FEED, feed.data(), feed.size());
    };
    scenes.push_back(s);
  }
  return scenes;
}

// FNV-1a of a buffer (the fixtures' expected.txt: the texture and agents read back at once
// after the checkpoint was written).
inline uint64_t Fnv1a(const void* data, size_t bytes) {
  uint64_t h = 1469598103934665603ull;
  const unsigned char* c = static_cast<const unsigned char*>(data);
  for (size_t i = 0; i < bytes; ++i) h = (h ^ c[i]) * 1099511628211ull;
  return h;
}

}  // namespace mtx

#endif  // MOLDTEX_TESTS_CHECKPOINT_SCENES_H
