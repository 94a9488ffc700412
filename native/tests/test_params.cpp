// Live parameters: set_params between steps takes effect without a reset.
#include "test_util.h"

namespace mtx {
namespace {

void ExpectSameParams(const moldtex_sim_params& a, const moldtex_sim_params& b) {
  EXPECT_EQ(a.movement_speed, b.movement_speed);
  EXPECT_EQ(a.turn_speed, b.turn_speed);
  EXPECT_EQ(a.vision_distance, b.vision_distance);
  EXPECT_EQ(a.vision_angle, b.vision_angle);
  EXPECT_EQ(a.evaporation_rate, b.evaporation_rate);
  EXPECT_EQ(a.diffusion_rate, b.diffusion_rate);
  EXPECT_EQ(a.deposit, b.deposit);
  EXPECT_EQ(a.time_step, b.time_step);
  EXPECT_EQ(a.substeps, b.substeps);
  EXPECT_EQ(a.thread_count, b.thread_count);
}

moldtex_sim_params Custom() {
  moldtex_sim_params p = default_params();
  p.movement_speed = 1.25f;
  p.turn_speed = 33.0f;
  p.vision_distance = 0.8f;
  p.vision_angle = 27.5f;
  p.evaporation_rate = 0.45f;
  p.diffusion_rate = 3.0f;
  p.deposit = 0.9f;
  p.time_step = 1.0f / 30.0f;
  p.substeps = 4;
  p.thread_count = 2;
  return p;
}

TEST(Params, CreateThenGetRoundTrips) {
  const Mesh m = make_quad();
  auto s = create_surface(m);
  ASSERT_TRUE(s) << LastError();
  const moldtex_sim_params p = Custom();
  const moldtex_sim_config c = make_config(96, 48, 1234, 0x123456789ABCDEFull);
  auto sim = create_sim(s.get(), c, p);
  ASSERT_TRUE(sim) << LastError();
  moldtex_sim_params got;
  moldtex_sim_params_init(&got);
  ASSERT_EQ(moldtex_sim_get_params(sim.get(), &got), MOLDTEX_OK) << LastError();
  ExpectSameParams(got, p);
  moldtex_sim_config gc;
  moldtex_sim_config_init(&gc);
  ASSERT_EQ(moldtex_sim_get_config(sim.get(), &gc), MOLDTEX_OK) << LastError();
  EXPECT_EQ(gc.width, 96u);
  EXPECT_EQ(gc.height, 48u);
  EXPECT_EQ(gc.agent_count, 1234u);
  EXPECT_EQ(gc.seed, 0x123456789ABCDEFull);
}

TEST(Params, StatsAfterCreate) {
  // A fresh simulation: no steps, no pheromone, the memory it holds is at least the
  // pheromone texture (one float per texel).
  const Mesh m = make_quad();
  auto s = create_surface(m);
  ASSERT_TRUE(s) << LastError();
  auto sim = create_sim(s.get(), make_config(64, 32, 500, 1), default_params());
  ASSERT_TRUE(sim) << LastError();
  moldtex_sim_stats st;
  moldtex_sim_stats_init(&st);
  ASSERT_EQ(moldtex_sim_get_stats(sim.get(), &st), MOLDTEX_OK) << LastError();
  EXPECT_EQ(st.step_count, 0u);
  EXPECT_EQ(st.agent_count, 500u);
  EXPECT_GE(st.bytes_in_use, 64u * 32u * sizeof(float));
  EXPECT_EQ(st.coverage, 0.0);
  EXPECT_EQ(st.presence, 0.0);
  ASSERT_EQ(moldtex_sim_step(sim.get(), 3), MOLDTEX_OK);
  EXPECT_EQ(get_stats(sim.get()).step_count, 3u);
}

TEST(Params, SetBetweenStepsTakesEffectWithoutReset) {
  // The artist tweaks a slider while the simulation runs: get_params returns the new
  // values at once, agents stay where they are, and the next step uses them:
  // deposit 0 with evaporation at the hard limit (1000/s: 16.7 per step) empties the
  // texture in one step, exactly.
  const Mesh m = make_quad();
  auto s = create_surface(m);
  ASSERT_TRUE(s) << LastError();
  auto sim = create_sim(s.get(), make_config(64, 64, 4000, 1), default_params());
  ASSERT_TRUE(sim) << LastError();
  ASSERT_EQ(moldtex_sim_step(sim.get(), 60), MOLDTEX_OK) << LastError();
  const auto st0 = get_stats(sim.get());
  ASSERT_GT(st0.coverage, 0.0);
  const auto agents0 = read_agents(sim.get(), 4000);

  moldtex_sim_params p = default_params();
  p.deposit = 0.0f;
  p.evaporation_rate = 1000.0f;
  ASSERT_EQ(moldtex_sim_set_params(sim.get(), &p), MOLDTEX_OK) << LastError();
  moldtex_sim_params got;
  moldtex_sim_params_init(&got);
  ASSERT_EQ(moldtex_sim_get_params(sim.get(), &got), MOLDTEX_OK);
  ExpectSameParams(got, p);
  const auto agents1 = read_agents(sim.get(), 4000);
  ASSERT_EQ(agents0.size(), agents1.size());
  EXPECT_EQ(0, std::memcmp(agents0.data(), agents1.data(),
                           agents0.size() * sizeof(moldtex_surface_point)))
      << "set_params must not respawn agents";
  EXPECT_EQ(get_stats(sim.get()).step_count, 60u);  // not reset

  ASSERT_EQ(moldtex_sim_step(sim.get(), 1), MOLDTEX_OK) << LastError();
  const auto st1 = get_stats(sim.get());
  EXPECT_EQ(st1.step_count, 61u);
  EXPECT_EQ(st1.coverage, 0.0);
  EXPECT_EQ(st1.presence, 0.0);
  for (float v : read_rgba(sim.get(), 64, 64)) ASSERT_TRUE(v == 0.0f || v == 1.0f);  // A = 1

  // Back to depositing: the pattern regrows from where the agents are.
  const moldtex_sim_params defaults = default_params();
  ASSERT_EQ(moldtex_sim_set_params(sim.get(), &defaults), MOLDTEX_OK) << LastError();
  ASSERT_EQ(moldtex_sim_step(sim.get(), 5), MOLDTEX_OK);
  EXPECT_GT(get_stats(sim.get()).coverage, 0.0);
}

TEST(Params, RejectedSetKeepsPreviousParams) {
  // A bad value is refused as a whole; the simulation keeps running on the old values.
  const Mesh m = make_quad();
  auto s = create_surface(m);
  ASSERT_TRUE(s) << LastError();
  const moldtex_sim_params good = Custom();
  auto sim = create_sim(s.get(), make_config(32, 32, 100, 1), good);
  ASSERT_TRUE(sim) << LastError();
  moldtex_sim_params bad = good;
  bad.deposit = 0.2f;                // a valid change ...
  bad.movement_speed = std::nanf("");  // ... next to an invalid one
  EXPECT_EQ(moldtex_sim_set_params(sim.get(), &bad), MOLDTEX_ERROR_INVALID_ARGUMENT);
  EXPECT_FALSE(LastError().empty());
  moldtex_sim_params got;
  moldtex_sim_params_init(&got);
  ASSERT_EQ(moldtex_sim_get_params(sim.get(), &got), MOLDTEX_OK);
  ExpectSameParams(got, good);
  EXPECT_EQ(moldtex_sim_step(sim.get(), 2), MOLDTEX_OK) << LastError();
}

TEST(Params, ResetKeepsCurrentParams) {
  // Reset respawns and clears, but keeps the parameters set since creation.
  const Mesh m = make_quad();
  auto s = create_surface(m);
  ASSERT_TRUE(s) << LastError();
  auto sim = create_sim(s.get(), make_config(32, 32, 100, 1), default_params());
  ASSERT_TRUE(sim) << LastError();
  const moldtex_sim_params p = Custom();
  ASSERT_EQ(moldtex_sim_set_params(sim.get(), &p), MOLDTEX_OK) << LastError();
  ASSERT_EQ(moldtex_sim_reset(sim.get()), MOLDTEX_OK) << LastError();
  moldtex_sim_params got;
  moldtex_sim_params_init(&got);
  ASSERT_EQ(moldtex_sim_get_params(sim.get(), &got), MOLDTEX_OK);
  ExpectSameParams(got, p);
}

TEST(ModelParams, OneCallPairReachesEveryModelsParameters) {
  // Issue 49: moldtex_sim_set/get_model_params take the struct of the model named, the
  // same as the calls per model; an unknown model is refused naming the models.
  auto s = create_surface(make_quad());
  auto sim = create_sim(s.get(), make_config(32, 32, 100, 1), default_params());
  moldtex_sim_params p = default_params();
  p.evaporation_rate = 0.625f;
  ASSERT_EQ(moldtex_sim_set_model_params(sim.get(), MOLDTEX_MODEL_MOMAS, &p), MOLDTEX_OK) << LastError();
  moldtex_sim_params p_back;
  moldtex_sim_params_init(&p_back);
  ASSERT_EQ(moldtex_sim_get_params(sim.get(), &p_back), MOLDTEX_OK);
  EXPECT_EQ(p_back.evaporation_rate, 0.625f);
  moldtex_continuous_params c;
  moldtex_continuous_params_init(&c);
  c.decay_rate = 0.3125f;
  ASSERT_EQ(moldtex_sim_set_model_params(sim.get(), MOLDTEX_MODEL_CONTINUOUS, &c), MOLDTEX_OK) << LastError();
  moldtex_continuous_params c_back;
  moldtex_continuous_params_init(&c_back);
  ASSERT_EQ(moldtex_sim_get_continuous_params(sim.get(), &c_back), MOLDTEX_OK);
  EXPECT_EQ(c_back.decay_rate, 0.3125f);
  moldtex_reaction_params r;
  moldtex_reaction_params_init(&r);
  r.feed = 0.0375f;
  ASSERT_EQ(moldtex_sim_set_reaction_params(sim.get(), &r), MOLDTEX_OK);
  moldtex_reaction_params r_back;
  moldtex_reaction_params_init(&r_back);
  ASSERT_EQ(moldtex_sim_get_model_params(sim.get(), MOLDTEX_MODEL_GRAY_SCOTT, &r_back), MOLDTEX_OK) << LastError();
  EXPECT_EQ(r_back.feed, 0.0375f);
  // Validated as the calls per model validate.
  c.decay_rate = -1.f;
  EXPECT_EQ(moldtex_sim_set_model_params(sim.get(), MOLDTEX_MODEL_CONTINUOUS, &c), MOLDTEX_ERROR_INVALID_ARGUMENT);
  EXPECT_NE(LastError().find("Decay rate"), std::string::npos) << LastError();
  EXPECT_EQ(moldtex_sim_set_model_params(sim.get(), MOLDTEX_MODEL_CONTINUOUS, nullptr),
            MOLDTEX_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(moldtex_sim_set_model_params(sim.get(), 7, &c), MOLDTEX_ERROR_INVALID_ARGUMENT);
  EXPECT_NE(LastError().find("Unknown model"), std::string::npos) << LastError();
  EXPECT_NE(LastError().find("Gray-Scott"), std::string::npos) << LastError();
  EXPECT_EQ(moldtex_sim_get_model_params(sim.get(), 7, &c), MOLDTEX_ERROR_INVALID_ARGUMENT);
}

}  // namespace
}  // namespace mtx
