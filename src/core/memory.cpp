#include "core/memory.h"

#include <sys/resource.h>
#include <unistd.h>

#include <cstdio>
#include <limits>

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
    double available = physicalMegabytes();
    // A process run under an address-space limit (ulimit -v, a service's sandbox) gets less.
    rlimit limit{};
    if (getrlimit(RLIMIT_AS, &limit) == 0 && limit.rlim_cur != RLIM_INFINITY) {
        const double cap = static_cast<double>(limit.rlim_cur) / (1024.0 * 1024.0);
        if (available <= 0.0 || cap < available) available = cap;
    }
    return 0.75 * available;  // room for the OS and the bake's last allocations
}

void checkMemoryBudget(double budget_mb, const char* during) {
    if (!(budget_mb > 0.0)) return;
    const double used = residentMegabytes();
    if (used > budget_mb) throw MemoryBudgetExceeded{used, budget_mb, during};
}

bool fitsMemoryBudget(double budget_mb, double bytes) {
    if (!(budget_mb > 0.0)) return true;
    return residentMegabytes() + bytes / (1024.0 * 1024.0) <= budget_mb;
}

std::string bytesText(double bytes) {
    char text[64];
    const double mib = bytes / (1024.0 * 1024.0);
    if (mib >= 1024.0) std::snprintf(text, sizeof text, "%.1f GiB", mib / 1024.0);
    else std::snprintf(text, sizeof text, "%.0f MiB", mib);
    return text;
}

std::string outOfMemoryMessage(const std::string& phase) {
    return "out of memory while " + phase +
           " (an allocation failed below the memory budget: the machine or the process's limits hold less; "
           "give --max-memory below what is available)";
}

namespace {
constexpr double kGaugeRereadBytes = 64.0 * 1024.0 * 1024.0;
}

MemoryGauge::MemoryGauge(double budget_mb) : budget_mb_(budget_mb) {
    if (budget_mb_ > 0.0) resident_mb_ = residentMegabytes();
}

bool MemoryGauge::reserve(double bytes) {
    if (!(budget_mb_ > 0.0)) return true;
    if (asked_ > kGaugeRereadBytes) {
        resident_mb_ = residentMegabytes();
        asked_ = 0.0;
    }
    if (!(resident_mb_ + (asked_ + bytes) / (1024.0 * 1024.0) <= budget_mb_)) return false;
    asked_ += bytes;
    return true;
}

bool MemoryGauge::fits(double bytes) {
    if (!(budget_mb_ > 0.0)) return true;
    resident_mb_ = residentMegabytes();
    asked_ = 0.0;
    return resident_mb_ + bytes / (1024.0 * 1024.0) <= budget_mb_;
}

double MemoryGauge::roomBytes() const {
    if (!(budget_mb_ > 0.0)) return std::numeric_limits<double>::infinity();
    return budget_mb_ * 1024.0 * 1024.0 - resident_mb_ * 1024.0 * 1024.0 - asked_;
}

}  // namespace radbake
