// Diffusion across UV seams: the blur must treat the surface as one piece, not each UV
// island as its own box (DESIGN.md lists "blur ignores UV seams and island borders, so
// trails fade or bleed at seams" among the reference code's defects to avoid).
#include <unordered_map>

#include "test_util.h"

namespace mtx {
namespace {

constexpr uint32_t kW = 128;  // cube layout: cells of 32 x 32 texels, islands ~27 wide

// Island (UV cell of the cube's cross layout) a texel lies in; the 2-texel gutter of an
// island stays inside its cell (the islands are inset by 2.56 texels).
int CubeCell(size_t texel) { return int((texel % kW) / 32) + 4 * int((texel / kW) / 32); }

// Standing agents deposit once, then the field only diffuses: deposit 0, no
// evaporation, diffusion_rate 60/s = a full 3x3 blur every step.
SimPtr DepositThenDiffuse(moldtex_surface s, uint32_t agents, uint32_t diffuse_steps,
                          double* coverage_after_deposit) {
  moldtex_sim_params p = default_params();
  p.movement_speed = 0;
  p.turn_speed = 0;
  p.evaporation_rate = 0;
  p.diffusion_rate = 0;
  p.deposit = 1;
  auto sim = create_sim(s, make_config(kW, kW, agents, 5), p);
  EXPECT_TRUE(sim) << LastError();
  if (!sim) return sim;
  EXPECT_EQ(moldtex_sim_step(sim.get(), 1), MOLDTEX_OK) << LastError();
  if (coverage_after_deposit) *coverage_after_deposit = get_stats(sim.get()).coverage;
  p.deposit = 0;
  p.diffusion_rate = 60;
  EXPECT_EQ(moldtex_sim_set_params(sim.get(), &p), MOLDTEX_OK) << LastError();
  EXPECT_EQ(moldtex_sim_step(sim.get(), diffuse_steps), MOLDTEX_OK) << LastError();
  return sim;
}

TEST(Diffusion, SpreadsAcrossSeamsToEveryIsland) {
  // One agent's single deposit on the cube, then 300 full blur steps: a 3x3 blur grows
  // the support by one texel per step, so pheromone reaches every texel of the
  // connected surface (the farthest is < 100 texels away across seams). Presence
  // must be 1 (> 0.99); if the blur stopped at seams it would stay at 1/6 (one island).
  const Mesh m = make_cube();
  auto s = create_surface(m);
  ASSERT_TRUE(s) << LastError();
  double deposited = 0;
  auto sim = DepositThenDiffuse(s.get(), 1, 300, &deposited);
  ASSERT_TRUE(sim);
  ASSERT_GT(deposited, 0.0);
  const auto st = get_stats(sim.get());
  EXPECT_GT(st.presence, 0.99) << "pheromone stayed on "
                               << st.presence * 6 << " of the cube's 6 faces";
  const auto rgba = read_rgba(sim.get(), kW, kW);
  const auto cls = read_classes(sim.get(), kW, kW);
  ASSERT_EQ(cls.size(), size_t(kW) * kW);
  std::unordered_map<int, double> per_island;
  for (size_t i = 0; i < cls.size(); ++i)
    if (cls[i] == MOLDTEX_TEXEL_INSIDE) per_island[CubeCell(i)] += rgba[4 * i];
  ASSERT_EQ(per_island.size(), 6u);
  for (const auto& [cell, sum] : per_island) EXPECT_GT(sum, 0.0) << "island in cell " << cell;
}

TEST(Diffusion, ConservesPheromoneOnAClosedSurface) {
  // The cube has no boundary: diffusion only moves pheromone around, so coverage
  // (the area-weighted mean, Eq. 1) stays what the deposit made it. 2%: gutter copies
  // at island corners need not be exactly conservative; a blur that loses pheromone
  // at island borders loses several % per step.
  const Mesh m = make_cube();
  auto s = create_surface(m);
  ASSERT_TRUE(s) << LastError();
  double deposited = 0;
  auto sim = DepositThenDiffuse(s.get(), 3000, 400, &deposited);
  ASSERT_TRUE(sim);
  ASSERT_GT(deposited, 0.1);
  EXPECT_NEAR(get_stats(sim.get()).coverage, deposited, 0.02 * deposited);
}

TEST(Diffusion, GutterNextToAnIslandCopiesTheOtherSideOfTheSeam) {
  // Header: gutter texels hold copies of their neighbours across the seam. Every cube
  // island edge is a seam, so a gutter texel beside an island (an inside texel directly
  // left, right, above or below it) must copy a texel of another island. Values are
  // made distinct by a few blur steps over scattered deposits, and a gutter texel
  // counts as a copy from island X when its value occurs only in island X.
  const Mesh m = make_cube();
  auto s = create_surface(m);
  ASSERT_TRUE(s) << LastError();
  auto sim = DepositThenDiffuse(s.get(), 400, 4, nullptr);
  ASSERT_TRUE(sim);
  const auto rgba = read_rgba(sim.get(), kW, kW);
  const auto cls = read_classes(sim.get(), kW, kW);
  ASSERT_EQ(cls.size(), size_t(kW) * kW);
  std::unordered_map<float, int> island_of_value;  // -1: value found in several islands
  for (size_t i = 0; i < cls.size(); ++i) {
    if (cls[i] != MOLDTEX_TEXEL_INSIDE || rgba[4 * i] == 0) continue;
    auto [it, fresh] = island_of_value.emplace(rgba[4 * i], CubeCell(i));
    if (!fresh && it->second != CubeCell(i)) it->second = -1;
  }
  size_t own = 0, other = 0;
  for (size_t i = 0; i < cls.size(); ++i) {
    if (cls[i] != MOLDTEX_TEXEL_GUTTER || rgba[4 * i] == 0) continue;
    const int x = int(i % kW), y = int(i / kW);
    bool beside = false;
    const int nb[4][2] = {{1, 0}, {-1, 0}, {0, 1}, {0, -1}};
    for (const auto& d : nb) {
      const int nx = x + d[0], ny = y + d[1];
      if (nx >= 0 && ny >= 0 && nx < int(kW) && ny < int(kW) &&
          cls[size_t(ny) * kW + nx] == MOLDTEX_TEXEL_INSIDE)
        beside = true;
    }
    if (!beside) continue;
    const auto it = island_of_value.find(rgba[4 * i]);
    if (it == island_of_value.end() || it->second < 0) continue;  // ambiguous value
    (it->second == CubeCell(i) ? own : other)++;
  }
  ASSERT_GT(own + other, 50u) << "too few distinct gutter values to judge";
  // Near island corners the texel across the seam may fall into a third island's
  // gutter; allow 10% own-island copies for those.
  EXPECT_LE(own, (own + other) / 10) << own << " gutter texels beside an island copy their own "
                                     << "island, " << other << " copy across the seam";
}

}  // namespace
}  // namespace mtx
