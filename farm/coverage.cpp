#include "farm/coverage.h"

#include "core/error.h"

#include <algorithm>
#include <cstdio>
#include <map>
#include <tuple>

namespace candela {

namespace {

// Reads exactly `count` integers separated by `separator` from `text`.
bool parse_ints(const std::string& text, char separator, int count, int* out) {
    size_t pos = 0;
    for (int i = 0; i < count; ++i) {
        size_t end = i + 1 < count ? text.find(separator, pos) : text.size();
        if (end == std::string::npos || end == pos) return false;
        std::string item = text.substr(pos, end - pos);
        size_t used = 0;
        try {
            out[i] = std::stoi(item, &used);
        } catch (const std::exception&) {
            return false;
        }
        if (used != item.size()) return false;
        pos = end + 1;
    }
    return true;
}

std::vector<int> breakpoints(std::vector<int> values) {
    std::sort(values.begin(), values.end());
    values.erase(std::unique(values.begin(), values.end()), values.end());
    return values;
}

}  // namespace

ImageRect parse_rect(const std::string& text) {
    int v[4];
    if (!parse_ints(text, ',', 4, v) || v[0] < 0 || v[1] < 0 || v[2] <= 0 || v[3] <= 0)
        throw InputError("expected a region x,y,width,height (non-negative corner, positive size), got \"" + text + "\"");
    return ImageRect{Vec2i(v[0], v[1]), Vec2i(v[2], v[3])};
}

SampleRange parse_sample_range(const std::string& text) {
    int v[2];
    if (!parse_ints(text, ':', 2, v) || v[0] < 0 || v[1] <= v[0])
        throw InputError("expected a sample range START:END with 0 <= START < END, got \"" + text + "\"");
    return SampleRange{v[0], v[1]};
}

std::string format_rect(const ImageRect& r) {
    return std::to_string(r.offset.x) + "," + std::to_string(r.offset.y) + "," + std::to_string(r.size.x) + "," + std::to_string(r.size.y);
}

std::string format_sample_range(const SampleRange& s) { return std::to_string(s.begin) + ":" + std::to_string(s.end); }

std::string format_coverage(const std::vector<CoverageBox>& boxes) {
    std::string out;
    for (const CoverageBox& b : boxes) out += (out.empty() ? "" : ";") + format_rect(b.rect) + "@" + format_sample_range(b.samples);
    return out;
}

std::vector<CoverageBox> parse_coverage(const std::string& text) {
    std::vector<CoverageBox> boxes;
    size_t pos = 0;
    while (pos <= text.size()) {
        size_t end = std::min(text.find(';', pos), text.size());
        std::string item = text.substr(pos, end - pos);
        size_t at = item.find('@');
        if (at == std::string::npos) throw InputError("malformed coverage \"" + item + "\" (expected x,y,w,h@start:end)");
        boxes.push_back(CoverageBox{parse_rect(item.substr(0, at)), parse_sample_range(item.substr(at + 1))});
        pos = end + 1;
    }
    return boxes;
}

bool overlap(const CoverageBox& a, const CoverageBox& b) {
    auto apart = [](int a0, int a1, int b0, int b1) { return a1 <= b0 || b1 <= a0; };
    const Vec2i a1 = a.rect.offset + a.rect.size, b1 = b.rect.offset + b.rect.size;
    return !(apart(a.rect.offset.x, a1.x, b.rect.offset.x, b1.x) || apart(a.rect.offset.y, a1.y, b.rect.offset.y, b1.y) ||
             apart(a.samples.begin, a.samples.end, b.samples.begin, b.samples.end));
}

CoverageBox whole_render(const Vec2i& image, int spp) { return CoverageBox{ImageRect{Vec2i(0), image}, SampleRange{0, spp}}; }

std::vector<CoverageBox> uncovered(const std::vector<CoverageBox>& covered, const CoverageBox& target) {
    // Cut the target at every box edge; in each cell, the sample ranges no box covers. Then join
    // cells missing the same range into rectangles, row runs first and then downwards.
    const Vec2i lo = target.rect.offset, hi = target.rect.offset + target.rect.size;
    const int s0 = target.samples.begin, s1 = target.samples.end;
    std::vector<int> xs = {lo.x, hi.x}, ys = {lo.y, hi.y};
    for (const CoverageBox& b : covered) {
        xs.push_back(std::clamp(b.rect.offset.x, lo.x, hi.x));
        xs.push_back(std::clamp(b.rect.offset.x + b.rect.size.x, lo.x, hi.x));
        ys.push_back(std::clamp(b.rect.offset.y, lo.y, hi.y));
        ys.push_back(std::clamp(b.rect.offset.y + b.rect.size.y, lo.y, hi.y));
    }
    xs = breakpoints(xs);
    ys = breakpoints(ys);
    const int nx = int(xs.size()) - 1, ny = int(ys.size()) - 1;
    std::map<std::pair<int, int>, std::vector<char>> missing_cells;  // sample range -> cell mask
    for (int j = 0; j < ny; ++j)
        for (int i = 0; i < nx; ++i) {
            std::vector<SampleRange> ranges;
            for (const CoverageBox& b : covered)
                if (b.rect.offset.x <= xs[i] && xs[i + 1] <= b.rect.offset.x + b.rect.size.x && b.rect.offset.y <= ys[j] &&
                    ys[j + 1] <= b.rect.offset.y + b.rect.size.y)
                    ranges.push_back(b.samples);
            std::sort(ranges.begin(), ranges.end(), [](const SampleRange& a, const SampleRange& b) { return a.begin < b.begin; });
            int next = s0;
            auto gap = [&](int a, int b) {
                auto& mask = missing_cells[{a, b}];
                mask.resize(size_t(nx) * ny, 0);
                mask[size_t(j) * nx + i] = 1;
            };
            for (const SampleRange& r : ranges) {
                if (r.begin > next) gap(next, std::min(r.begin, s1));
                next = std::max(next, r.end);
                if (next >= s1) break;
            }
            if (next < s1) gap(next, s1);
        }
    std::vector<CoverageBox> boxes;
    for (auto& [range, mask] : missing_cells)
        for (int j = 0; j < ny; ++j)
            for (int i = 0; i < nx; ++i) {
                if (!mask[size_t(j) * nx + i]) continue;
                int i1 = i;
                while (i1 < nx && mask[size_t(j) * nx + i1]) ++i1;
                int j1 = j + 1;
                while (j1 < ny &&
                       std::all_of(mask.begin() + size_t(j1) * nx + i, mask.begin() + size_t(j1) * nx + i1, [](char c) { return c; }))
                    ++j1;
                for (int jj = j; jj < j1; ++jj) std::fill(mask.begin() + size_t(jj) * nx + i, mask.begin() + size_t(jj) * nx + i1, 0);
                boxes.push_back(CoverageBox{ImageRect{Vec2i(xs[i], ys[j]), Vec2i(xs[i1] - xs[i], ys[j1] - ys[j])},
                                            SampleRange{range.first, range.second}});
            }
    return boxes;
}

std::vector<CoverageBox> coalesce(std::vector<CoverageBox> boxes) {
    auto key = [](const CoverageBox& b) {
        return std::make_tuple(b.rect.offset.y, b.rect.offset.x, b.rect.size.y, b.rect.size.x, b.samples.begin);
    };
    std::sort(boxes.begin(), boxes.end(), [&](const CoverageBox& a, const CoverageBox& b) { return key(a) < key(b); });
    std::vector<CoverageBox> out;
    for (const CoverageBox& b : boxes) {
        if (!out.empty() && out.back().rect.offset == b.rect.offset && out.back().rect.size == b.rect.size &&
            out.back().samples.end == b.samples.begin)
            out.back().samples.end = b.samples.end;
        else
            out.push_back(b);
    }
    return out;
}

std::string describe(const CoverageBox& box, const Vec2i& image) {
    std::string s = "samples " + format_sample_range(box.samples);
    if (box.rect.offset != Vec2i(0) || box.rect.size != image) s += " of pixels " + format_rect(box.rect);
    return s;
}

}  // namespace candela
