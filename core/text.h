#pragma once
// Splitting attribute text into its items, as Mitsuba's string::tokenize does for number lists.

#include <cctype>
#include <string>
#include <vector>

namespace candela {

// The items of "a, b c,d": separated by commas and/or white space, empty items dropped.
inline std::vector<std::string> split_list(const std::string& text) {
    std::vector<std::string> items;
    std::string item;
    for (char c : text) {
        if (c == ',' || std::isspace(static_cast<unsigned char>(c))) {
            if (!item.empty()) items.push_back(item);
            item.clear();
        } else {
            item += c;
        }
    }
    if (!item.empty()) items.push_back(item);
    return items;
}

}  // namespace candela
