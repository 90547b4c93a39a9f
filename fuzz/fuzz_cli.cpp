// libFuzzer target: the programs' command-line parsing (io/cli.hpp's CommandLine) as slab
// runs it (examples/slab_options.hpp: slab's option set, config_from and --phase), up to the checks its objects make when built (water, source,
// surface, transport settings), without tracing a photon. (Not the cone average of --omega:
// building its table takes longer than all the rest.) Then the same words through
// iop_profile's options and its START:STOP:STEP ranges (CommandLine::range).
//
// Input: the words of a command line (argv[1...]), separated by single spaces or newlines;
// one final newline is dropped. "--albedo  x" has an empty word between the two spaces.
// --json is left out (it creates a file), as is any material file.
//
// Checked: every rejection is a secchi::input_error. Any other exception (uncaught: abort),
// a crash, a sanitizer report or a hang is a finding, and so is a whole-number option that
// reaches slab's configuration as another number (narrowed to a smaller type).
#include "../examples/slab_options.hpp"
#include "secchi/io/cli.hpp"
#include "secchi/solver/phase_choice.hpp"
#include "secchi/solver/plane_parallel.hpp"
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

namespace {

/// argv[0] = "fuzz", then the words of `text`.
std::vector<std::string> words_of(std::string_view text) {
    if (!text.empty() && text.back() == '\n') text.remove_suffix(1);
    std::vector<std::string> words{"fuzz"};
    if (text.empty()) return words;
    words.emplace_back();
    for (const char c : text) {
        if (c == ' ' || c == '\n') words.emplace_back();
        else words.back().push_back(c);
    }
    return words;
}

/// slab's parsing and the checks of what it builds, short of the run.
void slab_options(int argc, char** argv) {
    const secchi::CommandLine cl = secchi::examples::slab::command_line(argc, argv);
    const secchi::PlaneParallelConfig cfg = secchi::examples::slab::config_from(cl);
    const secchi::AnyPhase phase = secchi::parse_phase(cl.text("phase", "petzold"));
    const auto same = [&](const char* option, std::uint64_t fallback, std::uint64_t configured) {
        if (cl.count(option, fallback) == configured) return;
        std::fprintf(stderr, "--%s %s is configured as %llu\n", option, cl.text(option).c_str(),
                     static_cast<unsigned long long>(configured));
        std::abort();
    };
    same("batches", 32, cfg.transport.batches);
    same("steps", 64, cfg.steps);
    same("ray-grid", 10, cfg.ray_grid);
    same("threads", 1, cfg.transport.threads);
    cfg.transport.validate();
    secchi::require_first_pass_fits_in_memory<secchi::CompactRecord>(cfg.transport);
    std::visit(
        [&](const auto& p) {
            using Phase = std::decay_t<decltype(p)>;
            (void)secchi::HomogeneousWater<Phase>::from_albedo(cfg.attenuation, cfg.albedo, p);
        },
        phase);
    (void)secchi::detail::source_of(cfg);
    (void)secchi::Slab(cfg.section_width, cfg.bottom);
    const double n = cfg.water_index.value_or(1.34);
    if (cfg.slopes.upwind != 0.0 || cfg.slopes.crosswind != 0.0) (void)secchi::WindBlownSurface(cfg.slopes, n, cfg.facets, 1.0, cfg.shadowing);
    else (void)secchi::FlatSurface(n);
}

/// iop_profile's options and ranges (examples/iop_profile.cpp's run(), short of the material).
void iop_profile_options(int argc, char** argv) {
    const secchi::CommandLine cl(argc, argv, {"material", "material-entry", "wavelengths", "depths", "seed", "out"},
                                 {"problem3"});
    (void)cl.range("wavelengths", "400:700:10");
    (void)cl.range("depths", "0:60:5", 0.0);
    (void)cl.count("seed", 1);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    std::vector<std::string> words = words_of(std::string_view(reinterpret_cast<const char*>(data), size));
    for (const auto& w : words)
        if (w == "--json" || w == "--out" || w == "--material") return 0;  // files: not fuzzed here
    std::vector<char*> argv;
    for (auto& w : words) argv.push_back(w.data());
    argv.push_back(nullptr);
    const int argc = static_cast<int>(words.size());
    try {
        slab_options(argc, argv.data());
    } catch (const secchi::input_error&) {
    }
    try {
        iop_profile_options(argc, argv.data());
    } catch (const secchi::input_error&) {
    }
    return 0;
}
