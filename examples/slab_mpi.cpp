// slab_mpi: slab (examples/slab.cpp) spread over the processes of an MPI run, e.g.
//     mpirun -n 4 slab_mpi --photons 1000000 --map-photons 1000000 --shards 4 --json out.json
// Same options; each rank traces its share of the batches and builds its shards of the map
// (solver/mpi_plane_parallel.hpp); rank 0 prints the table and writes the JSON, the same bits
// as `slab --shards S` with the same options (apart from the run time). Threads per rank:
// --threads. docs/distributed.md: the contract and the scaling model.
#include "slab_options.hpp"
#include "slab_report.hpp"
#include "slab_solve.hpp"
#include "secchi/io/cli.hpp"
#include "secchi/solver/mpi_plane_parallel.hpp"
#include "secchi/solver/phase_choice.hpp"
#include <mpi.h>
#include <optional>

int main(int argc, char** argv) {
    MPI_Init(&argc, &argv);
    namespace slab = secchi::examples::slab;
    const int status = secchi::run_program(argc, argv, "slab_mpi", slab::usage(), [&] {
        const secchi::CommandLine cl = slab::command_line(argc, argv);
        const auto cfg = slab::config_from(cl);
        const auto phase = secchi::parse_phase(cl.text("phase", "petzold"));
        const secchi::MpiSplit split(MPI_COMM_WORLD);
        std::optional<secchi::OutputFile> json;  // checked before the work, on rank 0
        if (split.rank() == 0 && cl.has("json")) json.emplace("--json", cl.text("json"));
        const auto result = slab::solve(phase, cfg, split);
        if (split.rank() == 0) {
            slab::print_table(result);
            if (json) slab::write_json(result, *json);
        }
        return 0;
    });
    MPI_Finalize();
    return status;
}
