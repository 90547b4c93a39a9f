// One small first pass, compiled into two units for two instruction sets (isa_mix_*.cpp).
// secchi's functions are inline, so without its ISA-tagged namespace (core/config.hpp) the two
// units' PhotonTracer would be one symbol and the linker would keep either compilation. (The
// test's own function has internal linkage for the same reason.)
#pragma once
#include "secchi/optics/medium.hpp"
#include "secchi/optics/phase/henyey_greenstein.hpp"
#include "secchi/transport/tracer.hpp"
#include "isa_run.hpp"


static IsaRun run_problem() {
    using namespace secchi;
    const HomogeneousWater<HenyeyGreensteinPhase> water(0.2, 0.8, HenyeyGreensteinPhase(0.9));
    TransportSettings run;
    run.photons = 20000;
    run.depths = {2.0};
    run.seed = 3;
    const auto r = PhotonTracer<HomogeneousWater<HenyeyGreensteinPhase>, CompactRecord>(
                       water, Slab(1.0, Bottom{}), FlatSurface(1.34), CollimatedSun(30.0), run)
                       .run();
    const Estimate ed = r.irradiance[0][IrradianceKind::Ed];
    return {isa_tag, ed.value, ed.se};
}
