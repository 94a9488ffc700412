// MoMaS' parts that its model (momas_model.cpp) hands out.
#pragma once
#include <cstddef>
#include <cstdint>
#include <memory>

namespace moldtex {

class CpuModelStep;

// Its CPU step, with the deposit marks of `texels` texels per species.
std::unique_ptr<CpuModelStep> momas_cpu_step(size_t texels, uint32_t species_count);

}  // namespace moldtex
