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

// The budget a bake runs under: `requested_mb` when positive, else 3/4 of physical memory,
// or of the process's address-space limit (RLIMIT_AS) when that is lower.
double memoryBudgetMegabytes(double requested_mb);

// Throws MemoryBudgetExceeded when resident memory is above `budget_mb` (> 0).
void checkMemoryBudget(double budget_mb, const char* during);

// Whether `bytes` more fit in `budget_mb` (<= 0: no budget) on top of resident memory now:
// asked before a large allocation, so a hostile file is refused before it is spent.
bool fitsMemoryBudget(double budget_mb, double bytes);

// "512 MiB", "3.2 GiB": sizes in messages.
std::string bytesText(double bytes);

// The message for an allocation that failed anyway (std::bad_alloc) in `phase`.
std::string outOfMemoryMessage(const std::string& phase);

// A stage's running account against the budget, for one that builds many pieces (the VRML
// builder's meshes): each piece's bytes are asked for before it is built. Resident memory is
// read again only after each 64 MiB asked, so asking is cheap.
class MemoryGauge {
public:
    explicit MemoryGauge(double budget_mb = 0.0);
    // False (nothing counted) when `bytes` more would take the process above the budget.
    bool reserve(double bytes);
    // Whether `bytes` more fit now (resident memory read again), without counting them.
    bool fits(double bytes);
    double budgetMegabytes() const { return budget_mb_; }
    // What the budget leaves now, in bytes (infinite without a budget).
    double roomBytes() const;

private:
    double budget_mb_ = 0.0;
    double resident_mb_ = 0.0;  // when last read
    double asked_ = 0.0;        // bytes asked since then
};

}  // namespace radbake
