#pragma once
// A BSDF plugin for parser tests: `<bsdf type="test_probe" id="name">` records every property it
// receives (by id) so a test can check what the loader produced.

#include "core/properties.h"

#include <map>
#include <string>

namespace candela::test {

// Properties of every probe built so far, by id.
std::map<std::string, Properties>& probes();

}  // namespace candela::test
