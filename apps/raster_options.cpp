#include "apps/commands.h"

#include "core/error.h"
#include "core/text.h"

namespace candela::app {

void RasterOptionArgs::add_to(CLI::App* cmd) {
    for (const RasterOption& o : raster_options()) {
        if (!o.command_line) continue;
        std::string flag = o.name;
        std::replace(flag.begin(), flag.end(), '_', '-');
        flag = "--" + flag;
        std::string help = std::string("Raster mode: ") + o.help;
        if (o.kind == RasterOption::Kind::Boolean) {
            cmd->add_flag(flag, flags[o.name], help);
            continue;
        }
        if (o.kind == RasterOption::Kind::Integer) help += " (" + o.accepted() + ")";
        // The value is checked when parsing, before anything asks whether the mode is raster.
        const std::string name = o.name;
        std::vector<std::string> choices(o.choices.begin(), o.choices.end());
        const CLI::Validator valid(
            [name, flag, choices](std::string& value) {
                RasterSettings scratch;
                std::string error;
                if (scratch.set(name, value, error)) return std::string();
                const std::string nearest = suggested_name(value, choices);
                return flag + ": " + error + (nearest.empty() ? "" : "; did you mean " + nearest + "?");
            },
            "");
        cmd->add_option(flag, values[o.name], help)->type_name(o.kind == RasterOption::Kind::Choice ? o.accepted() : "N")->check(valid);
    }
}

std::map<std::string, std::string> RasterOptionArgs::given() const {
    std::map<std::string, std::string> out;
    for (const auto& [name, value] : values)
        if (!value.empty()) out[name] = value;
    for (const auto& [name, on] : flags)
        if (on) out[name] = "true";
    return out;
}

void RasterOptionArgs::apply(RasterSettings& settings) const {
    std::string error;
    for (const auto& [name, value] : given())
        if (!settings.set(name, value, error)) throw InputError(error);
}

}  // namespace candela::app
