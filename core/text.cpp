#include "core/text.h"

namespace candela {

// Levenshtein distance, ignoring case: how many single-letter edits turn `a` into `b`.
size_t edit_distance(const std::string& a, const std::string& b) {
    std::vector<size_t> row(b.size() + 1);
    for (size_t j = 0; j <= b.size(); ++j) row[j] = j;
    for (size_t i = 1; i <= a.size(); ++i) {
        size_t diagonal = row[0];
        row[0] = i;
        for (size_t j = 1; j <= b.size(); ++j) {
            size_t above = row[j];
            bool same = std::tolower(static_cast<unsigned char>(a[i - 1])) == std::tolower(static_cast<unsigned char>(b[j - 1]));
            row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (same ? 0 : 1)});
            diagonal = above;
        }
    }
    return row[b.size()];
}

std::string nearest_name(const std::string& word, const std::vector<std::string>& names) {
    std::string best;
    size_t best_distance = 0;
    for (const std::string& name : names) {
        size_t d = edit_distance(word, name);
        if (best.empty() || d < best_distance) best = name, best_distance = d;
    }
    return best;
}

std::string suggested_name(const std::string& word, const std::vector<std::string>& names) {
    const std::string nearest = nearest_name(word, names);
    return !nearest.empty() && edit_distance(word, nearest) <= std::max<size_t>(2, word.size() / 3) ? nearest : std::string();
}

}  // namespace candela
