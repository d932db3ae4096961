#pragma once
// The process's memory, for budgets that stop a bake with a clear error before the kernel
// kills it (or an allocation fails after minutes).
#include <string>

namespace radbake {

// Resident memory of this process now, in MiB (/proc/self/statm; 0 when unknown).
double residentMegabytes();

// The machine's physical memory, in MiB (0 when unknown).
double physicalMegabytes();

// Thrown by a stage that finds the process above its budget; the stage's boundary turns it
// into a located error naming the budget.
struct MemoryBudgetExceeded {
    double used_mb = 0.0;
    double budget_mb = 0.0;
    std::string during;  // "linking", ...
};

// The budget a bake runs under: `requested_mb` when positive, else 3/4 of physical memory.
double memoryBudgetMegabytes(double requested_mb);

// Throws MemoryBudgetExceeded when resident memory is above `budget_mb` (> 0).
void checkMemoryBudget(double budget_mb, const char* during);

}  // namespace radbake
