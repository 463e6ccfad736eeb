#pragma once
// Small text helpers: splitting attribute text into its items, as Mitsuba's string::tokenize
// does for number lists, reading whole numbers, case folding for names Mitsuba reads
// case-insensitively, and escaping text for HTML and SVG output.

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
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

// Names joined by ',' ("R,G,B"): what split_list reads back, for names without commas or spaces.
inline std::string join_list(const std::vector<std::string>& names) {
    std::string out;
    for (const std::string& n : names) out += (out.empty() ? "" : ",") + n;
    return out;
}

// One item of such a list as a finite number: false when it is not one, whole.
inline bool parse_finite_float(const std::string& item, float& v) {
    size_t used = 0;
    try {
        v = std::stof(item, &used);
    } catch (...) {
        return false;
    }
    return used == item.size() && std::isfinite(v);
}

// `text`, all of it, as a base-10 integer (std::strtoll's syntax): false when it is not one.
// `out_of_range`, when given, tells an integer beyond long long's range from text that is none.
inline bool parse_integer(const std::string& text, long long& value, bool* out_of_range = nullptr) {
    if (out_of_range) *out_of_range = false;
    if (text.empty()) return false;
    char* end = nullptr;
    errno = 0;
    value = std::strtoll(text.c_str(), &end, 10);
    if (end != text.c_str() + text.size()) return false;
    if (errno == ERANGE) {
        if (out_of_range) *out_of_range = true;
        return false;
    }
    return true;
}

// A number with `digits` significant digits, enough to read it back exactly (9 for a float, 17
// for a double), as OpenImageIO prints attributes: "1" for 1, "0.100000001" for 0.1f.
inline std::string number_text(double v, int digits) {
    char text[40];
    std::snprintf(text, sizeof text, "%.*g", digits, v);
    return text;
}

// ASCII lower case (Mitsuba's string::to_lower).
inline std::string to_lower(std::string s) {
    std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    return s;
}

// `text` as HTML/XML character data or a quoted attribute value: the five characters with a
// meaning in markup become entities, so that a scene or file name shows as written and never
// becomes markup (or script) in a report.
inline std::string escape_markup(const std::string& text) {
    std::string out;
    out.reserve(text.size());
    for (char c : text) {
        switch (c) {
            case '&': out += "&amp;"; break;
            case '<': out += "&lt;"; break;
            case '>': out += "&gt;"; break;
            case '"': out += "&quot;"; break;
            case '\'': out += "&#39;"; break;
            default: out += c;
        }
    }
    return out;
}

// Levenshtein distance, ignoring case: how many single-letter edits turn `a` into `b`.
size_t edit_distance(const std::string& a, const std::string& b);
// The name in `names` closest to `word` by edit distance, ignoring case (ties: the first);
// empty when `names` is.
std::string nearest_name(const std::string& word, const std::vector<std::string>& names);
// For "did you mean": the nearest name when it is a plausible misspelling of `word` (at most
// max(2, a third of its letters) edits away), else "".
std::string suggested_name(const std::string& word, const std::vector<std::string>& names);

}  // namespace candela
