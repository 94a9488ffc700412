// Gray-Scott's parts that its model (gray_scott_model.cpp) hands out.
#pragma once
#include <memory>

namespace moldtex {

class CpuModelStep;

std::unique_ptr<CpuModelStep> gray_scott_cpu_step();

}  // namespace moldtex
