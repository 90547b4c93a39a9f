#include "problem.hpp"
IsaRun run_avx2() { return run_problem(); }
