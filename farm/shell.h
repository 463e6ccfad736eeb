#pragma once
// Words for a POSIX shell: the commands the farm prints, records in parts and writes into job
// scripts must survive spaces and quotes in file names.

#include <string>
#include <vector>

namespace candela {

// `word` unchanged when it holds only characters no shell treats specially, else single-quoted.
std::string shell_quote(const std::string& word);
// The words quoted and joined by spaces.
std::string shell_join(const std::vector<std::string>& words);

}  // namespace candela
