#include "core/image_draw.h"

#include <array>
#include <map>

namespace candela::draw {

Spectrum colormap_sequential(float t) {
    // Nine samples of matplotlib's viridis (van der Walt & Smith, 2015).
    static const std::array<Spectrum, 9> c = {
        Spectrum(0.267f, 0.005f, 0.329f), Spectrum(0.279f, 0.175f, 0.483f), Spectrum(0.230f, 0.322f, 0.546f),
        Spectrum(0.173f, 0.449f, 0.558f), Spectrum(0.128f, 0.567f, 0.551f), Spectrum(0.153f, 0.683f, 0.502f),
        Spectrum(0.369f, 0.789f, 0.383f), Spectrum(0.678f, 0.864f, 0.190f), Spectrum(0.993f, 0.906f, 0.144f)};
    t = std::clamp(std::isfinite(t) ? t : 0.0f, 0.0f, 1.0f) * float(c.size() - 1);
    int i = std::min(int(t), int(c.size()) - 2);
    float f = t - float(i);
    return c[i] * (1.0f - f) + c[i + 1] * f;
}

Spectrum colormap_diverging(float t) {
    t = std::clamp(std::isfinite(t) ? t : 0.0f, -1.0f, 1.0f);
    const Spectrum blue(0.23f, 0.30f, 0.75f), white(0.97f, 0.97f, 0.97f), red(0.71f, 0.02f, 0.15f);
    return t < 0.0f ? white * (1.0f + t) + blue * (-t) : white * (1.0f - t) + red * t;
}

namespace {
// 5x7 glyphs, one string of 7 rows x 5 columns per character ('#' = ink).
const std::map<char, const char*>& font() {
    static const std::map<char, const char*> glyphs = {
        {'0', ".###.#...##..###.#.###..##...#.###."}, {'1', "..#...##....#....#....#....#...###."},
        {'2', ".###.#...#....#...#...#...#...#####"}, {'3', "#####...#...#.....#.....##...#.###."},
        {'4', "...#...##..#.#.#..#.#####...#....#."}, {'5', "######....####.....#....##...#.###."},
        {'6', "..##..#...#....####.#...##...#.###."}, {'7', "#####....#...#...#...#....#....#..."},
        {'8', ".###.#...##...#.###.#...##...#.###."}, {'9', ".###.#...##...#.####....#...#..##.."},
        {'A', ".###.#...##...#######...##...##...#"}, {'B', "####.#...##...#####.#...##...#####."},
        {'C', ".###.#...##....#....#....#...#.###."}, {'D', "###..#..#.#...##...##...##..#.###.."},
        {'E', "######....#....####.#....#....#####"}, {'F', "######....#....####.#....#....#...."},
        {'G', ".###.#...##....#.####...##...#.####"}, {'H', "#...##...##...#######...##...##...#"},
        {'I', ".###...#....#....#....#....#...###."}, {'J', "..###...#....#....#....#.#..#..##.."},
        {'K', "#...##..#.#.#..##...#.#..#..#.#...#"}, {'L', "#....#....#....#....#....#....#####"},
        {'M', "#...###.###.#.##.#.##...##...##...#"}, {'N', "#...##...###..##.#.##..###...##...#"},
        {'O', ".###.#...##...##...##...##...#.###."}, {'P', "####.#...##...#####.#....#....#...."},
        {'Q', ".###.#...##...##...##.#.##..#..##.#"}, {'R', "####.#...##...#####.#.#..#..#.#...#"},
        {'S', ".#####....#.....###.....#....#####."}, {'T', "#####..#....#....#....#....#....#.."},
        {'U', "#...##...##...##...##...##...#.###."}, {'V', "#...##...##...##...##...#.#.#...#.."},
        {'W', "#...##...##...##.#.##.#.##.#.#.#.#."}, {'X', "#...##...#.#.#...#...#.#.#...##...#"},
        {'Y', "#...##...#.#.#...#....#....#....#.."}, {'Z', "#####....#...#...#...#...#....#####"},
        {'.', "..........................##...##.."}, {',', ".....................##....#...#..."},
        {'%', "##...##..#...#...#...#...#..##...##"}, {'-', "................###................"},
        {'+', ".......#....#..#####..#....#......."}, {':', "......##...##........##...##......."},
        {'/', ".........#...#...#...#...#........."}, {'(', "...#...#...#....#....#.....#.....#."},
        {')', ".#.....#.....#....#....#...#...#..."}, {'=', "..........#####.....#####.........."},
        {'_', "..............................#####"}, {' ', "..................................."},
        {'<', "...#...#...#...#.....#.....#.....#."}, {'>', ".#.....#.....#.....#...#...#...#..."},
        {'x', "..........#...#.#.#...#...#.#.#...#"}, {'^', "..#...#.#.#...#...................."},
    };
    return glyphs;
}
}  // namespace

int text_width(const std::string& s, int scale) { return int(s.size()) * 6 * scale; }

void text(Image& img, int x, int y, const std::string& s, const Spectrum& color, int scale) {
    for (size_t k = 0; k < s.size(); ++k) {
        char ch = s[k];
        if (ch >= 'a' && ch <= 'z' && ch != 'x') ch = char(ch - 'a' + 'A');
        auto it = font().find(ch);
        if (it == font().end()) it = font().find('?') != font().end() ? font().find('?') : font().find(' ');
        const char* g = it->second;
        for (int row = 0; row < 7; ++row)
            for (int col = 0; col < 5; ++col) {
                if (g[row * 5 + col] != '#') continue;
                for (int sy = 0; sy < scale; ++sy)
                    for (int sx = 0; sx < scale; ++sx) {
                        int px = x + (int(k) * 6 + col) * scale + sx, py = y + row * scale + sy;
                        if (px >= 0 && py >= 0 && px < img.width() && py < img.height()) img.set_rgb(px, py, color);
                    }
            }
    }
}

void fill_rect(Image& img, int x0, int y0, int x1, int y1, const Spectrum& color) {
    for (int y = std::max(0, y0); y < std::min(img.height(), y1); ++y)
        for (int x = std::max(0, x0); x < std::min(img.width(), x1); ++x) img.set_rgb(x, y, color);
}

void blit(Image& dst, const Image& src, int x0, int y0) {
    for (int y = 0; y < src.height(); ++y)
        for (int x = 0; x < src.width(); ++x) {
            int px = x0 + x, py = y0 + y;
            if (px >= 0 && py >= 0 && px < dst.width() && py < dst.height()) dst.set_rgb(px, py, src.rgb_at(x, y));
        }
}

Image with_legend(const Image& img, Spectrum (*map)(float), bool diverging, const std::vector<std::string>& labels,
                  const std::string& title) {
    int label_w = 0;
    for (auto& l : labels) label_w = std::max(label_w, text_width(l));
    int bar_w = 16, margin = 8;
    int width = img.width() + margin + bar_w + 4 + label_w + margin;
    int top = GlyphHeight + 2 * margin;
    int height = std::max(img.height(), 64) + top;
    Image out = Image::rgb(width, height);
    fill_rect(out, 0, 0, width, height, Spectrum(1.0f));
    text(out, margin, margin / 2 + 2, title, Spectrum(0.0f));
    blit(out, img, 0, top);
    int bar_x = img.width() + margin, bar_y0 = top + 4, bar_y1 = top + std::max(img.height(), 64) - 4;
    for (int y = bar_y0; y < bar_y1; ++y) {
        float t = 1.0f - float(y - bar_y0) / float(std::max(1, bar_y1 - bar_y0 - 1));  // 1 at top
        Spectrum c = diverging ? map(2.0f * t - 1.0f) : map(t);
        fill_rect(out, bar_x, y, bar_x + bar_w, y + 1, c);
    }
    for (size_t i = 0; i < labels.size(); ++i) {
        float f = labels.size() > 1 ? float(i) / float(labels.size() - 1) : 0.0f;
        int y = bar_y0 + int(f * float(bar_y1 - bar_y0 - 1));
        fill_rect(out, bar_x + bar_w, y, bar_x + bar_w + 3, y + 1, Spectrum(0.0f));
        text(out, bar_x + bar_w + 4, y - GlyphHeight / 2, labels[i], Spectrum(0.0f));
    }
    return out;
}

}  // namespace candela::draw
