// The continuous model's parts that its model (continuous_model.cpp) hands out.
#pragma once
#include <memory>

namespace moldtex {

class CpuModelStep;

std::unique_ptr<CpuModelStep> continuous_cpu_step();

}  // namespace moldtex
