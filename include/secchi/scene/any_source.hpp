#pragma once
// One of the light sources (scene/source.hpp), chosen at run time: a sun and a uniform sky at
// the surface (M93's set-up), a parametric sky (sun disk and Harrison-Coombes sky), or a traced
// atmosphere (M93 problem 4). A LightSource itself, each call going to the source it holds (one
// dispatch per photon launched and per photon going up from the surface), so that a program
// that lets its user choose compiles the first pass once.
#include "secchi/core/config.hpp"
#include "secchi/scene/atmosphere.hpp"
#include "secchi/scene/parametric_sky.hpp"
#include "secchi/scene/source.hpp"
#include "secchi/scene/sun_and_sky.hpp"
#include <string>
#include <variant>

namespace secchi::SECCHI_ISA {

class AnySource {
public:
    AnySource(SunAndSky s) : source_(std::move(s)) {}             // NOLINT(google-explicit-constructor)
    AnySource(ParametricSky s) : source_(std::move(s)) {}         // NOLINT(google-explicit-constructor)
    AnySource(TracedAtmosphere s) : source_(std::move(s)) {}      // NOLINT(google-explicit-constructor)

    [[nodiscard]] double plane_irradiance() const {
        return std::visit([](const auto& s) { return s.plane_irradiance(); }, source_);
    }
    [[nodiscard]] vec3 beam_direction() const {
        return std::visit([](const auto& s) { return s.beam_direction(); }, source_);
    }
    [[nodiscard]] SourcePhoton emit(PhotonRng& rng) const {
        return std::visit([&](const auto& s) { return s.emit(rng); }, source_);
    }
    [[nodiscard]] bool returns_light() const {
        return std::visit([](const auto& s) { return static_cast<bool>(s.returns_light()); }, source_);
    }
    [[nodiscard]] SourcePhoton reenter(const vec3& up, PhotonRng& rng) const {
        return std::visit([&](const auto& s) { return s.reenter(up, rng); }, source_);
    }

    /// The source held, if it is a T.
    template <class T>
    [[nodiscard]] const T* get_if() const {
        return std::get_if<T>(&source_);
    }
    /// "sun-and-sky", "parametric-sky" or "atmosphere".
    [[nodiscard]] std::string name() const {
        switch (source_.index()) {
            case 0: return "sun-and-sky";
            case 1: return "parametric-sky";
            default: return "atmosphere";
        }
    }

private:
    std::variant<SunAndSky, ParametricSky, TracedAtmosphere> source_;
};

static_assert(LightSource<AnySource>);

}  // namespace secchi
