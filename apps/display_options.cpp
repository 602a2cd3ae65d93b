#include "apps/display_options.h"

#include <cmath>
#include <cstdlib>
#include <map>
#include <string>

namespace prism::app {

void add_display_options(CLI::App* command, RenderSettings& settings) {
    command
        ->add_option("--exposure", settings.exposure,
                     "scale the light by 2^EV before the image is made (photographic stops; every output)")
        ->check(CLI::Validator(
            [](const std::string& text) -> std::string {
                // CLI::Range lets NaN through (it fails no comparison).
                char* end = nullptr;
                const double stops = std::strtod(text.c_str(), &end);
                if (end == text.c_str() || *end != '\0' || !(std::fabs(stops) <= 64.0))
                    return "expected a number of stops from -64 to 64, got " + text;
                return {};
            },
            "STOPS"))
        ->capture_default_str();
    const std::map<std::string, ToneMap> tone_maps = {{"none", ToneMap::None}, {"neutral", ToneMap::Neutral}};
    command
        ->add_option("--tone-map", settings.tone_map,
                     "none (values clip at 1, as the seed's) or neutral (Khronos PBR Neutral: highlights roll off "
                     "to white, base colours keep their hue)")
        ->transform(CLI::CheckedTransformer(tone_maps, CLI::ignore_case))
        ->default_str("none");
}

}  // namespace prism::app
