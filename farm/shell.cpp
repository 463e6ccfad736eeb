#include "farm/shell.h"

#include <cctype>

namespace candela {

std::string shell_quote(const std::string& word) {
    bool plain = !word.empty();
    for (char c : word)
        if (!std::isalnum(static_cast<unsigned char>(c)) && std::string("_-+=/.,:@%").find(c) == std::string::npos) plain = false;
    if (plain) return word;
    std::string out = "'";
    for (char c : word) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return out + "'";
}

std::string shell_join(const std::vector<std::string>& words) {
    std::string out;
    for (const std::string& w : words) out += (out.empty() ? "" : " ") + shell_quote(w);
    return out;
}

}  // namespace candela
