#pragma once
// slab's output (examples/slab.cpp, examples/slab_mpi.cpp): the table it prints and the JSON it
// writes with --json.
#include "secchi/io/cli.hpp"
#include "secchi/io/json_writer.hpp"
#include "secchi/solver/plane_parallel.hpp"
#include <cstdio>

namespace secchi::examples::slab {

inline void print_table(const secchi::PlaneParallelResult& r) {
    std::printf("phase %s: mean cosine %.5f, b_b/b %.5f, normalisation %.6f\n", r.phase_name.c_str(),
                r.moments.mean_cosine, r.moments.backscatter_fraction, r.moments.normalisation);
    std::printf("%llu photons traced, %llu stored, %.2f s\n", static_cast<unsigned long long>(r.photons_traced),
                static_cast<unsigned long long>(r.photons_stored), r.seconds);
    std::printf("first pass %.3f s, map build %.3f s, Lu %.3f s\n", r.seconds_transport, r.seconds_build,
                r.seconds_collect);
    std::printf("depth importance: %s\n", r.importance_choice.c_str());
    std::printf("%6s  %-21s %-21s %-21s %-21s %-21s\n", "tau", "Ed (se)", "Eu (se)", "Eod (se)", "Eou (se)", "Lu (se)");
    for (const auto& d : r.depths) {
        std::printf("%6.2f", d.depth);
        for (const auto& e : {d.irradiance[0], d.irradiance[1], d.irradiance[2], d.irradiance[3], d.lu})
            std::printf("  %.4e (%.1e)", e.value, e.se);
        std::printf("\n");
    }
    const auto& a = r.above;
    std::printf("source %s: just above the surface Ed(0+) = %.4e (direct %.4e, diffuse %.4e), Eu(0+) = %.4e\n",
                r.source_name.c_str(), a.ed_direct.value + a.ed_diffuse.value, a.ed_direct.value, a.ed_diffuse.value,
                a.eu.value);
}

inline void write_json(const secchi::PlaneParallelResult& r, secchi::OutputFile& file) {
    secchi::JsonWriter j(file.stream());
    j.begin_object();
    j.value("photons_traced", static_cast<unsigned long long>(r.photons_traced));
    j.value("photons_stored", static_cast<unsigned long long>(r.photons_stored));
    j.value("seconds", r.seconds);
    j.value("source", r.source_name);
    j.begin_object("above_surface")
        .value("Ed_direct", r.above.ed_direct.value)
        .value("Ed_direct_se", r.above.ed_direct.se)
        .value("Ed_diffuse", r.above.ed_diffuse.value)
        .value("Ed_diffuse_se", r.above.ed_diffuse.se)
        .value("Eu", r.above.eu.value)
        .value("Eu_se", r.above.eu.se)
        .end_object();
    j.begin_object("phase")
        .value("name", r.phase_name)
        .value("mean_cosine", r.moments.mean_cosine)
        .value("backscatter_fraction", r.moments.backscatter_fraction)
        .value("normalisation_integral", r.moments.normalisation)
        .end_object();
    j.begin_object("depth_importance")
        .value("cosine", r.importance.cosine)
        .value("max_depth", r.importance.max_depth)
        .value("chosen", r.importance_choice)
        .end_object();
    j.begin_array("depths");
    const char* names[] = {"Ed", "Eu", "Eod", "Eou"};
    const char* se_names[] = {"Ed_se", "Eu_se", "Eod_se", "Eou_se"};
    for (const auto& d : r.depths) {
        j.begin_object().value("tau", d.depth);
        for (int k = 0; k < 4; ++k) j.value(names[k], d.irradiance[k].value).value(se_names[k], d.irradiance[k].se);
        j.value("Lu", d.lu.value).value("Lu_se", d.lu.se).end_object();
    }
    j.end_array();
    j.end_object();
    file.commit();
}

}  // namespace secchi::examples::slab
