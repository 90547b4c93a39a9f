#pragma once
// A bounded water body: a square tank (a pool, a laboratory tank, a walled basin) of inner
// width L and depth D, its opaque walls of thickness t rising from its floor to the surface.
// secchi's water is a periodic section (scene/slab.hpp); a tank is that section, of width
// W = L + 2 t, with the walls standing along its four edges. Every periodic copy is then a
// closed tank, and no light passes from one copy into the next (the walls fill the section's
// border over the whole depth), so the section models one tank exactly: the copies are other
// tanks far away that nothing reaches. The tank's floor is the slab's bottom at D; light
// arriving over the walls' tops (the rim, at the surface) meets their material there. The
// surface must be flat: objects lie below a wave's troughs (transport/tracer.hpp).
//
//     const Tank tank{2.0, 0.1, 3.0, ObjectMaterial::lambertian(0.2)};
//     PhotonTracer<Water, CompactRecord, FlatSurface, SunAndSky, IrradiancePlanes, Bottom, Shapes>(
//         water, Slab(tank.section_width(), Bottom::lambertian_at(tank.depth, 0.3)), FlatSurface(1.34), sun,
//         settings, tank.walls()).run();
//
// The plane detectors and the bottom's Ed average over the whole section, walls included (no
// light reaches the floor under a wall); the bottom's bins resolve the tank's floor.
#include "secchi/core/config.hpp"
#include "secchi/core/error.hpp"
#include "secchi/scene/geometry.hpp"
#include "secchi/scene/shapes.hpp"
#include <cmath>

namespace secchi::SECCHI_ISA {

struct Tank {
    double inner_width;     ///< L (m): the water's extent in x and in y
    double wall_thickness;  ///< t (m)
    double depth;           ///< D (m): the floor, where the slab's bottom must be
    ObjectMaterial wall_material = ObjectMaterial::absorbing();

    /// The section holding the tank and its walls: W = L + 2 t.
    [[nodiscard]] double section_width() const { return inner_width + 2.0 * wall_thickness; }
    /// The inner region [t, t + L]^2 of the section, where the water is.
    [[nodiscard]] double inner_start() const { return wall_thickness; }

    /// The four walls as boxes from the surface (z = 0) to the floor (z = D): two full-width
    /// ones along x = 0 and x = W, two between them along y = 0 and y = W.
    [[nodiscard]] Shapes walls() const {
        require(std::isfinite(inner_width) && inner_width > 0.0, "tank inner width (m)", inner_width, "must be > 0");
        require(std::isfinite(wall_thickness) && wall_thickness > 0.0, "tank wall thickness (m)", wall_thickness,
                "must be > 0 (walls keep the periodic copies apart)");
        require(std::isfinite(depth) && depth > 0.0, "tank depth (m)", depth, "must be > 0");
        const double w = section_width(), t = wall_thickness;
        Shapes g;
        g.add(AxisBox({0.0, 0.0, 0.0}, {t, w, depth}), wall_material);
        g.add(AxisBox({w - t, 0.0, 0.0}, {w, w, depth}), wall_material);
        g.add(AxisBox({t, 0.0, 0.0}, {w - t, t, depth}), wall_material);
        g.add(AxisBox({t, w - t, 0.0}, {w - t, w, depth}), wall_material);
        return g;
    }
};

}  // namespace secchi
