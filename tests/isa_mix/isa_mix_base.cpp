#include "problem.hpp"
IsaRun run_base() { return run_problem(); }
