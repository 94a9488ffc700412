#include "backends/cpu/intrinsic_backend.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "common/error.h"
#include "domain/reaction_diffusion.h"

namespace moldtex {

namespace {

constexpr uint64_t kSortInterval = 16;
constexpr uint32_t kFacesPerGroup = 16;

uint64_t walker_key(const Walker& w) {
  uint32_t bits[6];
  bits[0] = w.triangle;
  std::memcpy(&bits[1], &w.bary[1], 4);
  std::memcpy(&bits[2], &w.bary[2], 4);
  std::memcpy(&bits[3], &w.heading.x, 4);
  std::memcpy(&bits[4], &w.heading.y, 4);
  bits[5] = 0x9e3779b9u;
  uint64_t h = 1469598103934665603ull;
  for (uint32_t b : bits) h = (h ^ b) * 1099511628211ull;
  return h;
}

bool same_walker(const Walker& a, const Walker& b) {
  return a.triangle == b.triangle && a.bary[1] == b.bary[1] && a.bary[2] == b.bary[2] &&
         a.heading.x == b.heading.x && a.heading.y == b.heading.y;
}

}  // namespace

IntrinsicCpuBackend::IntrinsicCpuBackend(std::shared_ptr<const Surface> surface,
                                         std::shared_ptr<const TextureDomain> texture,
                                         std::shared_ptr<const IntrinsicDomain> domain, uint32_t species_count,
                                         unsigned threads)
    : surface_(std::move(surface)),
      texture_(std::move(texture)),
      domain_(std::move(domain)),
      species_count_(species_count),
      pool_(std::make_unique<ThreadPool>(threads)) {
  const size_t n = static_cast<size_t>(domain_->vertex_count()) * species_count_;
  values_.assign(n, 0.f);
  sums_.assign(n, 0);
}

void IntrinsicCpuBackend::reset(const Agents& agents) {
  std::fill(values_.begin(), values_.end(), 0.f);
  std::fill(sums_.begin(), sums_.end(), 0);
  exported_.clear();
  exported_walkers_.clear();
  import_agents(agents);
}

void IntrinsicCpuBackend::set_thread_count(unsigned threads) {
  if (ThreadPool::resolve_thread_count(threads) != pool_->size()) pool_ = std::make_unique<ThreadPool>(threads);
}

void IntrinsicCpuBackend::set_field(const std::vector<float>& field) {
  field_ = field.empty() ? std::vector<float>{} : domain_->sample_texels(field.data());
}

void IntrinsicCpuBackend::import_agents(const Agents& agents) {
  Agents next = agents;
  next.batch.resize(next.size(), 0);
  pool_->parallel_for(next.size(), 256, [&](size_t begin, size_t end) {
    for (size_t i = begin; i < end; ++i) {
      const Walker w = next.load(i);
      const auto it = exported_walkers_.find(walker_key(w));
      if (it != exported_walkers_.end() && same_walker(it->second.first, w))
        next.store(i, it->second.second);
      else
        next.store(i, domain_->to_intrinsic(w));
    }
  });
  agents_ = std::move(next);
  exported_walkers_.clear();
}

void IntrinsicCpuBackend::export_agents(Agents& agents) const {
  agents = agents_;
  pool_->parallel_for(agents.size(), 256, [&](size_t begin, size_t end) {
    for (size_t i = begin; i < end; ++i) agents.store(i, domain_->to_input(agents_.load(i)));
  });
  exported_walkers_.clear();
  exported_walkers_.reserve(agents.size());
  for (size_t i = 0; i < agents.size(); ++i) {
    const Walker w = agents.load(i);
    exported_walkers_.emplace(walker_key(w), std::make_pair(w, agents_.load(i)));
  }
}

void IntrinsicCpuBackend::read_agents(moldtex_surface_point* out, size_t count) const {
  const size_t n = std::min(count, agents_.size());
  pool_->parallel_for(n, 256, [&](size_t begin, size_t end) {
    for (size_t i = begin; i < end; ++i) {
      const Walker w = domain_->to_input(agents_.load(i));
      out[i].triangle = w.triangle;
      std::copy(w.bary, w.bary + 3, out[i].bary);
    }
  });
}

const ParameterMaps& IntrinsicCpuBackend::vertex_maps(const ParameterMaps& maps) {
  if (vmaps_source_ == &maps && vmaps_version_ == maps.version) return vmaps_;
  const IntrinsicDomain& d = *domain_;
  const size_t texels = texture_->texel_count(), nv = d.vertex_count();
  ParameterMaps v;
  for (uint32_t k = 0; k < MOLDTEX_MAP_COUNT; ++k)
    if (!maps.given[k].empty()) v.given[k] = d.sample_texels(maps.given[k].data());
  const size_t planes = texels ? maps.agent_planes.size() / texels : 0;
  v.agent_planes.resize(planes * nv);
  for (size_t p = 0; p < planes; ++p) {
    const std::vector<float> s = d.sample_texels(maps.agent_planes.data() + p * texels);
    std::copy(s.begin(), s.end(), v.agent_planes.begin() + p * nv);
  }
  std::copy(std::begin(maps.plane_of), std::end(maps.plane_of), std::begin(v.plane_of));
  v.deposit_max = maps.deposit_max;
  v.largest = maps.largest;
  v.version = maps.version;
  // The spawn map: each face's largest vertex weight, and faces drawn by area times
  // their mean weight (the respawn rule of shared/continuous.h, on the faces).
  const int32_t spawn = maps.plane_of[MTX_MAP_SPAWN];
  if (spawn >= 0) {
    const float* w = v.agent_planes.data() + static_cast<size_t>(spawn) * nv;
    const uint32_t nf = d.face_count();
    v.spawn_max.resize(nf);
    std::vector<double> weights(nf);
    for (uint32_t f = 0; f < nf; ++f) {
      const uint32_t* c = d.face_vertices.data() + 3ull * f;
      v.spawn_max[f] = std::max({w[c[0]], w[c[1]], w[c[2]]});
      weights[f] = double(d.face_area[f]) * (double(w[c[0]]) + w[c[1]] + w[c[2]]) / 3.0;
    }
    v.spawn_alias = build_alias_table(weights);
  }
  vmaps_ = std::move(v);
  vmaps_source_ = &maps;
  vmaps_version_ = maps.version;
  return vmaps_;
}

const std::vector<float>& IntrinsicCpuBackend::face_bias(const std::vector<float>& bias) {
  if (bias.empty()) {
    bias_source_.clear();
    bias_faces_.clear();
    return bias_faces_;
  }
  if (bias == bias_source_) return bias_faces_;
  // Each face takes the bias of the input triangle under its centre, turned from that
  // triangle's frame into the face's: the face's x axis is found on the input mesh.
  const IntrinsicDomain& d = *domain_;
  std::vector<float> out(2ull * d.face_count(), 0.f);
  pool_->parallel_for(d.face_count(), 256, [&](size_t begin, size_t end) {
    for (size_t f = begin; f < end; ++f) {
      Walker w{};
      w.triangle = static_cast<uint32_t>(f);
      w.bary[0] = w.bary[1] = w.bary[2] = 1.f / 3.f;
      w.heading = {1.f, 0.f};
      const Walker in = d.to_input(w);
      const float bx = bias[2ull * in.triangle], by = bias[2ull * in.triangle + 1];
      // The face's x axis is `in.heading` in the triangle's frame: turn back by its angle.
      const float c = in.heading.x, s = in.heading.y;
      out[2 * f] = c * bx + s * by;
      out[2 * f + 1] = -s * bx + c * by;
    }
  });
  bias_source_ = bias;
  bias_faces_ = std::move(out);
  return bias_faces_;
}

void IntrinsicCpuBackend::step(const StepSettings& settings, uint64_t seed, uint64_t step_index,
                               uint32_t* /*eaters: food is MoMaS only*/) {
  exported_.clear();
  exported_walkers_.clear();
  if (settings.model == MOLDTEX_MODEL_CONTINUOUS) return step_continuous(settings, seed, step_index);
  if (settings.model == MOLDTEX_MODEL_GRAY_SCOTT) return step_gray_scott(settings);
  fail(MOLDTEX_ERROR_INVALID_ARGUMENT,
       "The Intrinsic domain runs the continuous model and Gray-Scott; MoMaS works in texels: use the Texture domain");
}

void IntrinsicCpuBackend::step_continuous(const StepSettings& settings, uint64_t seed, uint64_t step_index) {
  const IntrinsicDomain& d = *domain_;
  const ParameterMaps& maps = vertex_maps(*settings.maps);
  // Agents drift apart in memory order as they move; regroup them now and then (the
  // faces are numbered along a space-filling curve).
  if (step_index % kSortInterval == 0) sort_by_face(agents_, d.face_count(), kFacesPerGroup);
  ContinuousStepConstants c = continuous_constants(settings, *texture_, settings.u_metric, d.face_count(),
                                                   agents_.size(), seed, step_index);
  c.width = d.vertex_count();  // planes of vertex values
  c.height = 1;
  const std::vector<float>& bias = face_bias(settings.bias);
  const mtx_surface_tables tables = d.tables();
  const float* field = c.has_fields && !field_.empty() ? field_.data() : nullptr;
  if (!field) c.has_fields = 0;
  const AliasTable& alias = maps.spawn_max.empty() ? d.alias : maps.spawn_alias;
  pool_->parallel_for(agents_.size(), 1024, [&](size_t begin, size_t end) {
    continuous_update_agents(tables, c, values_.data(), field, sums_.data(), alias,
                             c.bias_on || c.bias_spawn ? bias.data() : nullptr, maps.agent_planes.data(),
                             maps.spawn_max.data(), agents_, begin, end);
  });
  settle_continuous_step(settings, maps, laplacian_for(maps, d.laplacian, mapped_), mapped_, c.deposit_units,
                         values_.data(), sums_.data(), pde_scratch_, species_count_, *pool_);
}

void IntrinsicCpuBackend::step_gray_scott(const StepSettings& settings) {
  const IntrinsicDomain& d = *domain_;
  if (species_count_ < kReactionPlanes) fail(MOLDTEX_ERROR_INTERNAL, "The Gray-Scott model needs two planes");
  const ParameterMaps& maps = vertex_maps(*settings.maps);
  reaction_step(laplacian_for(maps, d.laplacian, mapped_), settings.reaction, values_.data(), scratch_,
                d.vertex_count(), *pool_,
                reaction_maps(maps.feed(), maps.largest[MOLDTEX_MAP_FEED], maps.kill(),
                              maps.largest[MOLDTEX_MAP_KILL], settings.reaction));
}

void IntrinsicCpuBackend::read_pheromone(float* out) const {
  const size_t texels = texture_->texel_count(), nv = domain_->vertex_count();
  std::fill(out, out + texels * species_count_, 0.f);
  for (uint32_t k = 0; k < species_count_; ++k) {
    domain_->gather(values_.data() + k * nv, out + k * texels, *pool_);
    fill_gutter(*texture_, out + k * texels, *pool_);
  }
}

void IntrinsicCpuBackend::export_state(SimState& state) const {
  export_agents(state.agents);
  state.pheromone.assign(texture_->texel_count() * species_count_, 0.f);
  read_pheromone(state.pheromone.data());
  exported_ = state.pheromone;
}

void IntrinsicCpuBackend::import_state(const SimState& state) {
  const size_t texels = texture_->texel_count(), nv = domain_->vertex_count();
  if (state.pheromone.size() != texels * species_count_)
    fail(MOLDTEX_ERROR_INTERNAL, "The state's planes do not match the texture");
  const std::vector<uint32_t>& at = domain_->vertex_texel;
  std::vector<float> next = values_;
  for (uint32_t k = 0; k < species_count_; ++k) {
    const float* in = state.pheromone.data() + k * texels;
    float* out = next.data() + k * nv;
    if (exported_.size() == state.pheromone.size()) {
      const float* was = exported_.data() + k * texels;
      for (size_t v = 0; v < nv; ++v)
        if (in[at[v]] != was[at[v]]) out[v] += in[at[v]] - was[at[v]];
    } else {
      for (size_t v = 0; v < nv; ++v) out[v] = in[at[v]];
    }
  }
  import_agents(state.agents);
  values_ = std::move(next);
  exported_.clear();
}

std::string IntrinsicCpuBackend::name() const {
  const unsigned n = pool_->size();
  return "CPU (" + std::to_string(n) + (n == 1 ? " thread" : " threads") + ", intrinsic domain)";
}

size_t IntrinsicCpuBackend::bytes() const {
  return agents_.bytes() + (values_.capacity() + scratch_.capacity() + field_.capacity() + pde_scratch_.capacity()) * 4 +
         sums_.capacity() * 4 + vmaps_.agent_planes.capacity() * 4 + bias_faces_.capacity() * 4 + domain_->bytes();
}

}  // namespace moldtex
