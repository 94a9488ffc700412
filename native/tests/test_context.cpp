// Issue 49: a context handle owns the intrinsic domain cache that was a hidden process-wide
// static. Simulations in one context reuse its domains; another context, or the default
// one, does not see them; clearing or releasing a context drops them, and what its
// simulations use stays alive.
#include "test_util.h"

namespace mtx {
namespace {

moldtex_sim_config IntrinsicConfig() {
  moldtex_sim_config c = make_config(32, 32, 200, 3);
  c.model = MOLDTEX_MODEL_CONTINUOUS;
  c.domain = MOLDTEX_DOMAIN_INTRINSIC;
  c.backend = MOLDTEX_BACKEND_CPU;
  return c;
}

// Whether a new simulation in `context` took its domain from the cache.
bool FromCache(moldtex_context context, moldtex_surface surface, SimPtr* keep = nullptr) {
  const moldtex_sim_config c = IntrinsicConfig();
  const moldtex_sim_params p = default_params();
  moldtex_sim sim = nullptr;
  EXPECT_EQ(moldtex_sim_create_in(context, surface, &c, &p, &sim), MOLDTEX_OK) << LastError();
  moldtex_domain_info info;
  moldtex_domain_info_init(&info);
  EXPECT_EQ(moldtex_sim_get_domain_info(sim, &info), MOLDTEX_OK);
  if (keep)
    keep->reset(sim);
  else
    moldtex_sim_release(sim);
  return info.from_cache != 0;
}

uint32_t Cached(moldtex_context context) {
  uint32_t n = 99;
  EXPECT_EQ(moldtex_context_cached_domains(context, &n), MOLDTEX_OK);
  return n;
}

TEST(Context, OwnsItsIntrinsicDomainCache) {
  // A mesh of its own: no other test's simulation has put it in the default cache.
  auto surface = create_surface(make_torus(20, 10, 1.0, 0.3125));
  moldtex_context a = nullptr, b = nullptr;
  ASSERT_EQ(moldtex_context_create(&a), MOLDTEX_OK);
  ASSERT_EQ(moldtex_context_create(&b), MOLDTEX_OK);
  EXPECT_EQ(Cached(a), 0u);
  EXPECT_FALSE(FromCache(a, surface.get()));  // built
  EXPECT_EQ(Cached(a), 1u);
  EXPECT_TRUE(FromCache(a, surface.get()));   // reused within a
  EXPECT_FALSE(FromCache(b, surface.get()));  // b has its own
  EXPECT_FALSE(FromCache(nullptr, surface.get()));  // and so has the default context
  EXPECT_TRUE(FromCache(nullptr, surface.get()));
  // Clearing a drops its domains, not the others'.
  ASSERT_EQ(moldtex_context_clear(a), MOLDTEX_OK);
  EXPECT_EQ(Cached(a), 0u);
  EXPECT_EQ(Cached(b), 1u);
  EXPECT_TRUE(FromCache(b, surface.get()));
  // A simulation outlives its context, and keeps stepping on its domain.
  SimPtr kept;
  EXPECT_FALSE(FromCache(a, surface.get(), &kept));
  moldtex_context_release(a);
  EXPECT_EQ(moldtex_sim_step(kept.get(), 3), MOLDTEX_OK) << LastError();
  EXPECT_EQ(get_stats(kept.get()).step_count, 3u);
  // A domain built ahead lands in the context it was started in.
  const moldtex_sim_config c = IntrinsicConfig();
  ASSERT_EQ(moldtex_context_clear(b), MOLDTEX_OK);
  moldtex_domain_build build = nullptr;
  ASSERT_EQ(moldtex_domain_build_start_in(b, surface.get(), &c, 2, &build), MOLDTEX_OK) << LastError();
  EXPECT_EQ(moldtex_domain_build_wait(build), MOLDTEX_OK) << LastError();
  moldtex_domain_build_release(build);
  EXPECT_EQ(Cached(b), 1u);
  EXPECT_TRUE(FromCache(b, surface.get()));
  moldtex_context_release(b);
  // Bad arguments.
  EXPECT_EQ(moldtex_context_create(nullptr), MOLDTEX_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(moldtex_context_cached_domains(nullptr, nullptr), MOLDTEX_ERROR_INVALID_ARGUMENT);
  moldtex_context_release(nullptr);  // (as free(NULL))
}

}  // namespace
}  // namespace mtx
