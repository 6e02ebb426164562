// examples/quadcast/bench_stability.cpp -- `quadcast bench stability` (filled in with the root formulations)
#include "commands.hpp"

namespace quadcast::cli {

void add_bench_stability(CLI::App& bench) {
    bench.add_subcommand("stability", "float error of the root formulations against an MPFR reference");
}

}  // namespace quadcast::cli
