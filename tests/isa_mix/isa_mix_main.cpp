// A program mixing units built for two instruction sets (baseline and -mavx2 -mfma): each
// unit's secchi lives in its own inline namespace (core/config.hpp), so each calls its own
// compilation of PhotonTracer, and both give the same problem's answer.
#include "isa_run.hpp"
#include <cmath>
#include <cstdio>
#include <cstring>

IsaRun run_base();
IsaRun run_avx2();

int main() {
    const IsaRun base = run_base();
    std::printf("%s: Ed = %.10g (se %.2g)\n", base.tag, base.ed, base.ed_se);
    if (!__builtin_cpu_supports("avx2") || !__builtin_cpu_supports("fma")) {
        std::printf("this CPU lacks AVX2 or FMA: the AVX2 unit is linked but not run\n");
        return 0;
    }
    const IsaRun avx2 = run_avx2();
    std::printf("%s: Ed = %.10g (se %.2g)\n", avx2.tag, avx2.ed, avx2.ed_se);
    if (std::strcmp(base.tag, avx2.tag) == 0) {
        std::printf("FAIL: both units have the namespace tag %s\n", base.tag);
        return 1;
    }
    // Same photons, same seed: the two compilations differ at most where fused multiply-adds
    // round differently, which can turn a photon's path; the estimates agree well within an SE.
    if (!(std::abs(base.ed - avx2.ed) <= base.ed_se)) {
        std::printf("FAIL: the two units disagree by more than one standard error\n");
        return 1;
    }
    return 0;
}
