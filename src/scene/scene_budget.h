#pragma once
// Geometry asked of the memory budget before a reader builds it (both readers use these).
#include <string>

#include "core/memory.h"

namespace radbake {

// What a mesh of this many vertices and triangles holds through the import (its arrays, the
// copies hard-edge splitting may add, validation's scratch): asked of the budget before it is built.
double meshBytesEstimate(double vertices, double triangles);

// The located error for geometry that does not fit the budget.
std::string overBudgetMessage(const std::string& what, double meshes, double triangles, double bytes,
                              const MemoryGauge& memory);

}  // namespace radbake
