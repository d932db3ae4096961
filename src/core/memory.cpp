#include "core/memory.h"

#include <unistd.h>

#include <cstdio>

namespace radbake {

double residentMegabytes() {
    std::FILE* file = std::fopen("/proc/self/statm", "r");
    if (!file) return 0.0;
    long pages_total = 0, pages_resident = 0;
    const int read = std::fscanf(file, "%ld %ld", &pages_total, &pages_resident);
    std::fclose(file);
    if (read != 2) return 0.0;
    return static_cast<double>(pages_resident) * static_cast<double>(sysconf(_SC_PAGESIZE)) / (1024.0 * 1024.0);
}

double physicalMegabytes() {
    const long pages = sysconf(_SC_PHYS_PAGES), page = sysconf(_SC_PAGESIZE);
    return pages > 0 && page > 0 ? static_cast<double>(pages) * static_cast<double>(page) / (1024.0 * 1024.0) : 0.0;
}

double memoryBudgetMegabytes(double requested_mb) {
    if (requested_mb > 0.0) return requested_mb;
    return 0.75 * physicalMegabytes();  // room for the OS and the bake's last allocations
}

void checkMemoryBudget(double budget_mb, const char* during) {
    if (!(budget_mb > 0.0)) return;
    const double used = residentMegabytes();
    if (used > budget_mb) throw MemoryBudgetExceeded{used, budget_mb, during};
}

}  // namespace radbake
