#pragma once
// `candela farm status WORKDIR`: which parts of a farm render exist, which are missing (with the
// commands that render them and, for Slurm, the resubmission), and the time left estimated from
// the parts' recorded render times.

#include <string>

namespace candela {

// The report, several lines. InputError when WORKDIR holds no plan.
std::string farm_status(const std::string& workdir);

}  // namespace candela
