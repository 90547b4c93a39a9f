// slab: one plane-parallel problem (M93's base problem and its variants) from the command
// line. Prints a table of Ed, Eu, Eod, Eou and Lu with standard errors, and writes JSON.
// Run with --help for the options and their defaults.
// The options and their reading: slab_options.hpp; the table and the JSON: slab_report.hpp.
#include "slab_options.hpp"
#include "slab_report.hpp"
#include "slab_solve.hpp"
#include "secchi/io/cli.hpp"
#include "secchi/solver/phase_choice.hpp"
#include <optional>

int main(int argc, char** argv) {
    namespace slab = secchi::examples::slab;
    return secchi::run_program(argc, argv, "slab", slab::usage(), [&] {
        const secchi::CommandLine cl = slab::command_line(argc, argv);
        const auto cfg = slab::config_from(cl);
        const auto phase = secchi::parse_phase(cl.text("phase", "petzold"));
        std::optional<secchi::OutputFile> json;  // checked before the work
        if (cl.has("json")) json.emplace("--json", cl.text("json"));
        const auto result = slab::solve(phase, cfg);
        slab::print_table(result);
        if (json) slab::write_json(result, *json);
        return 0;
    });
}
