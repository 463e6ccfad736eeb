#include "farm/merge.h"

#include "core/error.h"
#include "farm/shell.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>

namespace fs = std::filesystem;

namespace candela {

namespace {

// The part files named: files as they are, folders as their *.exr files in name order (hidden
// files, such as the temporaries of writes still running or killed, are not parts).
std::vector<std::string> expand_paths(const std::vector<std::string>& paths) {
    std::vector<std::string> files;
    for (const std::string& p : paths) {
        std::error_code ec;
        if (!fs::is_directory(p, ec)) {
            files.push_back(p);
            continue;
        }
        std::vector<std::string> found;
        for (const auto& entry : fs::directory_iterator(p, ec)) {
            const std::string name = entry.path().filename().string();
            if (entry.is_regular_file(ec) && name[0] != '.' && entry.path().extension() == ".exr") found.push_back(entry.path().string());
        }
        if (ec) throw InputError(p + ": cannot list the folder: " + ec.message());
        if (found.empty()) throw InputError(p + ": the folder holds no parts (*.exr)");
        std::sort(found.begin(), found.end());
        files.insert(files.end(), found.begin(), found.end());
    }
    if (files.empty()) throw InputError("no parts given");
    return files;
}

struct OwnedBox {
    CoverageBox box;
    size_t part;
};

// Every pair of overlapping boxes of different parts (or of one part) is an error: sorted by their
// first sample index, a box can only overlap those that start before it ends.
void check_overlaps(const std::vector<PartHeader>& parts, const Vec2i& image) {
    std::vector<OwnedBox> boxes;
    for (size_t i = 0; i < parts.size(); ++i)
        for (const CoverageBox& b : parts[i].coverage) boxes.push_back({b, i});
    std::sort(boxes.begin(), boxes.end(), [](const OwnedBox& a, const OwnedBox& b) { return a.box.samples.begin < b.box.samples.begin; });
    for (size_t i = 0; i < boxes.size(); ++i)
        for (size_t j = i + 1; j < boxes.size() && boxes[j].box.samples.begin < boxes[i].box.samples.end; ++j) {
            if (!overlap(boxes[i].box, boxes[j].box)) continue;
            const PartHeader &a = parts[boxes[i].part], &b = parts[boxes[j].part];
            throw InputError(a.path + " and " + b.path + " overlap: " + describe(boxes[i].box, image) + " against " +
                             describe(boxes[j].box, image) + " (the same samples would count twice)");
        }
}

// The bounding rectangle of the parts' pixels.
ImageRect bounds(const std::vector<PartHeader>& parts) {
    Vec2i lo = parts[0].rect.offset, hi = lo;
    for (const PartHeader& p : parts) {
        lo = glm::min(lo, p.rect.offset);
        hi = glm::max(hi, p.rect.offset + p.rect.size);
    }
    return ImageRect{lo, hi - lo};
}

// One part at a time: memory is the sums of `area` plus one part.
PixelSums add_parts(const MergeSet& set, const ImageRect& area) {
    PixelSums sums(area, set.identity.values(), set.identity.layout());
    for (const PartHeader& p : set.parts) add_part(p, sums);
    return sums;
}

// What the parts together record about their making.
PartHeader summed_header(const MergeSet& set) {
    PartHeader h;
    h.identity = set.identity;
    h.started = set.parts[0].started;
    h.host = set.parts[0].host;
    h.rendered_parts = 0;
    for (const PartHeader& p : set.parts) {
        h.work.add_work(p.work);
        h.started = std::min(h.started, p.started);
        h.finished = std::max(h.finished, p.finished);
        if (p.host != h.host) h.host = "several";
        h.rendered_parts += p.rendered_parts;
        h.partial = h.partial || p.partial;
        h.coverage.insert(h.coverage.end(), p.coverage.begin(), p.coverage.end());
    }
    h.coverage = coalesce(h.coverage);
    return h;
}

}  // namespace

MergeSet check_parts(const std::vector<std::string>& paths) {
    MergeSet set;
    std::vector<std::string> files = expand_paths(paths);
    for (const std::string& f : files) {
        PartHeader h = read_part_header(f);
        for (const PartHeader& seen : set.parts) {
            std::error_code ec;
            if (fs::equivalent(seen.path, f, ec)) throw InputError(f + ": given twice");
        }
        if (set.parts.empty()) {
            set.identity = h.identity;
        } else if (std::string d = set.identity.difference(h.identity); !d.empty()) {
            throw InputError(f + ": belongs to another render than " + set.parts[0].path + ": " + d);
        }
        set.parts.push_back(std::move(h));
    }
    check_overlaps(set.parts, set.identity.image);
    std::vector<CoverageBox> all;
    for (const PartHeader& p : set.parts) all.insert(all.end(), p.coverage.begin(), p.coverage.end());
    set.missing = uncovered(all, whole_render(set.identity.image, set.identity.spp));
    return set;
}

std::string render_command_for(const RenderIdentity& id, const CoverageBox& box, const Vec2i& image, const std::string& output) {
    std::string cmd = id.command + " --samples " + format_sample_range(box.samples);
    if (box.rect.offset != Vec2i(0) || box.rect.size != image) cmd += " --crop " + format_rect(box.rect);
    return cmd + " -o " + shell_quote(output);
}

std::string describe_missing(const MergeSet& set) {
    const fs::path folder = fs::path(set.parts[0].path).parent_path();
    std::string out;
    for (const CoverageBox& b : set.missing) {
        std::string name = "part-" + std::to_string(b.samples.begin) + "-" + std::to_string(b.samples.end);
        if (b.rect.offset != Vec2i(0) || b.rect.size != set.identity.image)
            name += "-" + std::to_string(b.rect.offset.x) + "-" + std::to_string(b.rect.offset.y) + "-" + std::to_string(b.rect.size.x) +
                    "-" + std::to_string(b.rect.size.y);
        out += "  missing " + describe(b, set.identity.image) + "; render it with:\n    " +
               render_command_for(set.identity, b, set.identity.image, (folder / (name + ".exr")).string()) + "\n";
    }
    return out;
}

Image merge_image(const MergeSet& set) {
    const ImageRect whole{Vec2i(0), set.identity.image};
    Image image = add_parts(set, whole).develop();
    const PartHeader h = summed_header(set);
    const RenderIdentity& id = set.identity;
    RenderStats stats;  // of all the parts together
    stats.add_work(h.work);
    stats.spp = id.spp;
    stats.seed = id.seed;
    stats.sampler = id.sampler;
    stats.partial = !set.missing.empty();
    annotate_image(image, stats, id.integrator, id.scene);
    auto& m = image.metadata;
    m["candela.version"] = id.version;  // the parts' (the merging program's is in "software")
    m["candela.sceneHash"] = id.scene_hash;
    m["candela.mergedParts"] = std::to_string(h.rendered_parts);
    if (!set.missing.empty()) m["candela.missing"] = format_coverage(set.missing);
    return image;
}

void merge_into_part(const MergeSet& set, const std::string& output) {
    write_part(output, add_parts(set, bounds(set.parts)), summed_header(set));
}

}  // namespace candela
