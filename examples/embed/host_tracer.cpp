// A host ray tracer that takes its water from secchi: the living example of the embedding
// contract (estimate/radiance.hpp). The host owns the geometry (spheres and boxes, its own
// vector type and intersection code), the camera, the shading of its objects and its threads;
// secchi owns the water: the light scattered into each camera ray, the ray's transmittance,
// the sun's direct beam at a point, and the ambient light field. Per pixel:
//
//     no object on the ray:  L = est.radiance({o, d, INFINITY})
//                            (the water, the surface from below, the sky through Snell's
//                            window, the bottom: everything the ray meets is secchi's)
//     object at distance t:  L = est.radiance({o, d, t}) + est.transmittance({o, d, t}) L_obj
//                            (secchi's path radiance up to t only, plus the object's own
//                            radiance carried to the camera)
//
// The object's radiance is the host's choice; here Lambertian, albedo A:
//     L_obj = A / pi (E_sun max(0, n . s) V + E_amb(z, n))
// with E_sun the sun's E_perp at the point from est.direct_sun() (refracted at the surface and
// attenuated along the beam), s the direction towards the sun there, V = 0 where the host's
// own shadow ray towards the sun meets another of its objects before the surface, and E_amb
// the diffuse light from secchi's radiance distribution: the downwelling plane irradiance
// without the direct beam (Ed - E_sun mu_sun) on a face looking up, the upwelling Eu on a face
// looking down, weighted by (1 -+ n_z) / 2 in between; tabulated by irradiances_from_map at
// depths at most 1.5 m apart over the objects' depth range, linear in depth between them.
// The ray's transmittance is that of the estimator's optics, exp(-c' t): the scattering
// within the collection cone counts as unscattered (c' = c - b f), consistently with the path
// radiance, which leaves that light out. The sun's disk (a delta in direction) is not part of
// radiance(); this host does not draw it.
//
// Units: radiances in W m^-2 sr^-1 nm^-1 and irradiances in W m^-2 nm^-1 for a sun of
// E_perp = 1 W m^-2 nm^-1 above the surface (E_perp: its irradiance on a plane normal to the
// beam), i.e. per unit solar E_perp; everything scales linearly with the sun's and sky's
// actual spectral irradiance at the band's wavelength.
//
// What is approximate: the objects do not change the photon map. Their shadows darken only
// other objects (through the host's shadow rays), never the water's own light field, the
// bottom or the light scattered towards the camera, and light they reflect is not scattered
// again by the water. E_amb ignores the occlusion of the ambient light by other objects and is
// exact only for faces looking straight up or down. The photon-map estimates are statistical
// (the L.se channel: the scatter of the map's photon batches, and the ambient table's SE), and
// the map is a periodic section 1 m wide: a long ray gathers the same stored photons again in
// every section it crosses, so neighbouring pixels' noise is correlated and shows the lattice
// as faint streaks towards its vanishing points.
//
// Threads: the estimator is const after construction and its queries (radiance, add,
// transmittance, direct_sun; irradiances_from_map) may run on any number of threads at once;
// the host renders rows on its own std::threads. Each pixel is computed alone, without random
// numbers, so the image is the same for any thread count.
//
// Lifetimes: the estimator refers to the photon map, which must outlive it (here both live
// until main returns); an estimator constructed from a temporary map does not compile.
//
// Bands: the map traced here holds one band, and every query is for band 0.
//
// Coordinates: the host's world is secchi's (metres, z positive down, the surface at z = 0,
// the bottom at z = 8 m). A host with another frame (y up, z up) converts at the boundary,
// to_secchi() below. The objects lie in the water between the surface and the bottom:
// radiance() ends a ray at the nearest of t_max, the surface and the bottom, so an object
// beyond a boundary would be hidden by what secchi draws there.
#include <secchi/estimate/radiance_distribution.hpp>
#include <secchi/io/cli.hpp>
#include <secchi/io/exr.hpp>
#include <secchi/io/png_preview.hpp>
#include <secchi/optics/phase/petzold.hpp>
#include <secchi/solver/plane_parallel.hpp>
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <exception>
#include <limits>
#include <mutex>
#include <numbers>
#include <optional>
#include <string>
#include <thread>
#include <vector>

namespace host {

// ---- The host's own geometry ------------------------------------------------------------

struct Vec {
    double x = 0.0, y = 0.0, z = 0.0;
};
inline Vec operator+(Vec a, Vec b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
inline Vec operator-(Vec a, Vec b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
inline Vec operator-(Vec a) { return {-a.x, -a.y, -a.z}; }
inline Vec operator*(double s, Vec a) { return {s * a.x, s * a.y, s * a.z}; }
inline double dot(Vec a, Vec b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
inline Vec cross(Vec a, Vec b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }
inline Vec normalize(Vec a) { return (1.0 / std::sqrt(dot(a, a))) * a; }

/// The boundary between the host's vectors and secchi's (glm::dvec3, the same frame here).
inline secchi::vec3 to_secchi(Vec a) { return {a.x, a.y, a.z}; }
inline Vec from_secchi(const secchi::vec3& a) { return {a.x, a.y, a.z}; }

struct Sphere {
    Vec centre;
    double radius;
    double albedo;
};

/// An axis-aligned box [lo, hi].
struct Box {
    Vec lo, hi;
    double albedo;
};

struct Hit {
    double t;    ///< distance along the (unit) ray
    Vec point;
    Vec normal;  ///< outward unit normal
    double albedo;
};

/// The nearest intersection in (t_min, t_max) of the ray o + t d with a sphere.
inline std::optional<double> intersect(const Sphere& s, Vec o, Vec d, double t_min, double t_max) {
    const Vec oc = o - s.centre;
    const double b = dot(oc, d), c = dot(oc, oc) - s.radius * s.radius;
    const double disc = b * b - c;
    if (disc < 0.0) return std::nullopt;
    const double root = std::sqrt(disc);
    for (const double t : {-b - root, -b + root})
        if (t > t_min && t < t_max) return t;
    return std::nullopt;
}

/// The slab method: the nearest intersection in (t_min, t_max) with a box, and its face's normal.
inline std::optional<std::pair<double, Vec>> intersect(const Box& box, Vec o, Vec d, double t_min, double t_max) {
    const double os[3] = {o.x, o.y, o.z}, ds[3] = {d.x, d.y, d.z};
    const double lo[3] = {box.lo.x, box.lo.y, box.lo.z}, hi[3] = {box.hi.x, box.hi.y, box.hi.z};
    double t_in = -std::numeric_limits<double>::infinity(), t_out = std::numeric_limits<double>::infinity();
    int axis_in = 0, axis_out = 0;
    double sign_in = 0.0, sign_out = 0.0;
    for (int k = 0; k < 3; ++k) {
        if (ds[k] == 0.0) {
            if (os[k] < lo[k] || os[k] > hi[k]) return std::nullopt;
            continue;
        }
        double t0 = (lo[k] - os[k]) / ds[k], t1 = (hi[k] - os[k]) / ds[k];
        double s0 = -1.0, s1 = 1.0;  // entering through the low face: outward normal -axis
        if (t0 > t1) {
            std::swap(t0, t1);
            std::swap(s0, s1);
        }
        if (t0 > t_in) t_in = t0, axis_in = k, sign_in = s0;
        if (t1 < t_out) t_out = t1, axis_out = k, sign_out = s1;
    }
    if (t_in > t_out) return std::nullopt;
    const auto axis_normal = [](int k, double s) {
        Vec n;
        (k == 0 ? n.x : k == 1 ? n.y : n.z) = s;
        return n;
    };
    if (t_in > t_min && t_in < t_max) return std::pair{t_in, axis_normal(axis_in, sign_in)};
    if (t_out > t_min && t_out < t_max) return std::pair{t_out, axis_normal(axis_out, sign_out)};  // from inside
    return std::nullopt;
}

struct Scene {
    std::vector<Sphere> spheres;
    std::vector<Box> boxes;

    /// The nearest object along o + t d, t in (t_min, t_max).
    [[nodiscard]] std::optional<Hit> intersect(Vec o, Vec d, double t_min, double t_max) const {
        std::optional<Hit> best;
        for (const Sphere& s : spheres)
            if (const auto t = host::intersect(s, o, d, t_min, t_max)) {
                t_max = *t;
                const Vec p = o + *t * d;
                best = Hit{*t, p, (1.0 / s.radius) * (p - s.centre), s.albedo};
            }
        for (const Box& b : boxes)
            if (const auto h = host::intersect(b, o, d, t_min, t_max)) {
                t_max = h->first;
                best = Hit{h->first, o + h->first * d, h->second, b.albedo};
            }
        return best;
    }
    /// The depth range the objects occupy.
    [[nodiscard]] std::pair<double, double> depth_range() const {
        double top = INFINITY, bottom = -INFINITY;
        for (const Sphere& s : spheres) {
            top = std::min(top, s.centre.z - s.radius);
            bottom = std::max(bottom, s.centre.z + s.radius);
        }
        for (const Box& b : boxes) {
            top = std::min(top, b.lo.z);
            bottom = std::max(bottom, b.hi.z);
        }
        return {top, bottom};
    }
};

/// A diver swimming across the view at about 4.6 m (a chain of spheres), a buoy at 2.3-3.3 m,
/// a rock and a crate on the bottom (8 m). The sun's beam in the water travels towards -x and
/// down, 0.40 m across per metre down (the sun at 30 deg, refracted to 21.9 deg), so the
/// diver's shadow falls on the crate's top.
inline Scene demo_scene() {
    Scene s;
    s.spheres = {
        {{-0.85, 5.4, 4.50}, 0.20, 0.50},  // diver: head
        {{-0.35, 5.4, 4.60}, 0.34, 0.45},  //        torso
        {{0.20, 5.4, 4.65}, 0.27, 0.45},   //        hips
        {{0.65, 5.4, 4.70}, 0.19, 0.45},   //        legs
        {{1.00, 5.4, 4.75}, 0.15, 0.70},   //        fins
        {{-2.6, 6.5, 2.8}, 0.50, 0.80},    // buoy
        {{2.3, 5.2, 7.35}, 0.65, 0.25},    // rock, resting on the bottom
    };
    s.boxes = {{{-2.0, 5.2, 7.0}, {-0.6, 6.6, 8.0}, 0.55}};  // crate on the bottom
    return s;
}

/// The host's pinhole camera: pixel (x, y), row 0 at the top, through the pixel's centre.
class Camera {
public:
    Camera(Vec position, Vec forward, double vertical_fov_deg, int width, int height)
        : position_(position), forward_(normalize(forward)), width_(width), height_(height) {
        const Vec world_up{0.0, 0.0, -1.0};  // z is depth
        right_ = normalize(cross(forward_, world_up));
        up_ = cross(right_, forward_);
        half_height_ = std::tan(0.5 * vertical_fov_deg * std::numbers::pi / 180.0);
    }
    [[nodiscard]] Vec position() const { return position_; }
    [[nodiscard]] int width() const { return width_; }
    [[nodiscard]] int height() const { return height_; }
    [[nodiscard]] Vec direction(int x, int y) const {
        const double sx = (2.0 * (x + 0.5) / width_ - 1.0) * half_height_ * width_ / height_;
        const double sy = (1.0 - 2.0 * (y + 0.5) / height_) * half_height_;
        return normalize(forward_ + sx * right_ + sy * up_);
    }

private:
    Vec position_, forward_, right_, up_;
    int width_, height_;
    double half_height_ = 0.0;
};

/// Runs row(y) for y in [0, rows) on `threads` of the host's own threads; the first exception
/// a row throws stops the rest and is rethrown here. Finished rows go to secchi's progress
/// sink (core/progress.hpp), as a loop of secchi's own would.
template <class Row>
void for_each_row(int rows, unsigned threads, Row&& row) {
    std::atomic<int> next{0};
    std::exception_ptr error;
    std::mutex error_mutex;
    const secchi::ProgressLoop progress(static_cast<std::size_t>(rows));
    const auto worker = [&] {
        for (int y; (y = next.fetch_add(1)) < rows;) {
            try {
                row(y);
                progress.advanced();
            } catch (...) {
                const std::lock_guard lock(error_mutex);
                if (!error) error = std::current_exception();
                next = rows;
            }
        }
    };
    std::vector<std::jthread> pool;
    for (unsigned t = 1; t < threads; ++t) pool.emplace_back(worker);
    worker();
    pool.clear();  // joins
    if (error) std::rethrow_exception(error);
}

// ---- The light secchi gives the host ----------------------------------------------------

/// The diffuse (not direct-beam) plane irradiances from secchi's radiance distribution at
/// depths top, top + step, ..., linear in between: Ed without the sun's beam (on a face looking
/// up) and Eu (on a face looking down), W m^-2 nm^-1 per unit solar E_perp, with their SE.
class AmbientTable {
public:
    /// Depths from top to bottom, at most max_step apart.
    template <class Estimator>
    AmbientTable(const Estimator& est, double top, double bottom, double max_step, unsigned threads) : top_(top) {
        const int intervals = std::max(1, static_cast<int>(std::ceil((bottom - top) / max_step)));
        step_ = (bottom - top) / intervals;
        // 8 x 8 direction cells per hemisphere, 4 replicate groups: 512 rays per depth.
        const secchi::DirectionSampling sampling{8, 8, 4, 1};
        for (int k = 0; k <= intervals; ++k) {
            const double z = k == intervals ? bottom : top + k * step_;
            const secchi::MapIrradiances e = secchi::irradiances_from_map(est, z, sampling, threads);
            const secchi::Estimate ed = e.irradiance[secchi::Ed], eu = e.irradiance[secchi::Eu];
            down_.push_back({ed.value - e.direct[secchi::Ed], ed.se});
            up_.push_back(eu);
            depths_.push_back(z);
        }
    }
    /// Diffuse irradiance on a face at depth z whose outward normal has vertical component n_z
    /// (-1: looking up, +1: looking down): Ed_diffuse (1 - n_z) / 2 + Eu (1 + n_z) / 2.
    [[nodiscard]] secchi::Estimate on_face(double z, double n_z) const {
        const double u = std::clamp((z - top_) / step_, 0.0, static_cast<double>(depths_.size() - 1));
        const std::size_t i = std::min(static_cast<std::size_t>(u), depths_.size() - 2);
        const double f = u - static_cast<double>(i);
        const auto lerp = [&](const std::vector<secchi::Estimate>& v) {
            return secchi::Estimate{(1.0 - f) * v[i].value + f * v[i + 1].value, (1.0 - f) * v[i].se + f * v[i + 1].se};
        };
        const secchi::Estimate d = lerp(down_), up = lerp(up_);
        const double wd = 0.5 * (1.0 - n_z), wu = 0.5 * (1.0 + n_z);
        // The two estimates share the map's photons: their SEs add linearly (an upper bound).
        return {wd * d.value + wu * up.value, wd * d.se + wu * up.se};
    }
    [[nodiscard]] const std::vector<double>& depths() const { return depths_; }
    [[nodiscard]] const std::vector<secchi::Estimate>& ed_diffuse() const { return down_; }
    [[nodiscard]] const std::vector<secchi::Estimate>& eu() const { return up_; }

private:
    double top_, step_ = 0.0;
    std::vector<double> depths_;
    std::vector<secchi::Estimate> down_, up_;
};

/// A Lambertian object's radiance, split into the direct sun's part (exact given the water's
/// IOPs) and the ambient part (from the photon map, with its SE).
struct ObjectRadiance {
    double sun = 0.0;
    secchi::Estimate ambient;
    bool shadowed = false;
    [[nodiscard]] double value() const { return sun + ambient.value; }
};

template <class Estimator>
ObjectRadiance shade(const Scene& scene, const Estimator& est, const AmbientTable& ambient, const Hit& hit) {
    constexpr double inv_pi = 1.0 / std::numbers::pi;
    ObjectRadiance out;
    // The beam at the hit point: refracted at the surface, attenuated along its path in water.
    const secchi::DirectBeam beam = est.direct_sun(to_secchi(hit.point));
    const Vec to_sun = -from_secchi(beam.direction);  // the beam's direction is the light's travel
    const double cos_i = dot(hit.normal, to_sun);
    if (cos_i > 0.0 && beam.e_perp > 0.0) {
        // The host's shadow ray: towards the sun, up to the surface (the water itself does not
        // shadow: its attenuation is in beam.e_perp already).
        const double to_surface = hit.point.z / -to_sun.z;
        out.shadowed = scene.intersect(hit.point + 1e-6 * hit.normal, to_sun, 0.0, to_surface).has_value();
        if (!out.shadowed) out.sun = hit.albedo * inv_pi * beam.e_perp * cos_i;
    }
    const secchi::Estimate e = ambient.on_face(hit.point.z, hit.normal.z);
    out.ambient = {hit.albedo * inv_pi * e.value, hit.albedo * inv_pi * e.se};
    return out;
}

/// One pixel's radiance and what it is made of.
struct Pixel {
    secchi::Estimate radiance;
    std::optional<Hit> hit;
    secchi::Estimate path;      ///< secchi's in-scattered radiance up to the object (or the whole ray)
    double transmittance = 0.0; ///< from the camera to the object
    ObjectRadiance object;
};

template <class Estimator>
Pixel trace_pixel(const Scene& scene, const Estimator& est, const AmbientTable& ambient, const Camera& camera, int x,
                  int y) {
    const Vec o = camera.position(), d = camera.direction(x, y);
    Pixel px;
    px.hit = scene.intersect(o, d, 0.0, INFINITY);
    if (!px.hit) {
        // Open water: everything along the ray is secchi's.
        px.path = px.radiance = est.radiance(secchi::Ray{to_secchi(o), to_secchi(d), INFINITY}, 0);
        return px;
    }
    const secchi::Ray to_object{to_secchi(o), to_secchi(d), px.hit->t};
    px.path = est.radiance(to_object, 0);
    px.transmittance = est.transmittance(to_object);
    px.object = shade(scene, est, ambient, *px.hit);
    const double t = px.transmittance;
    px.radiance = {px.path.value + t * px.object.value(), std::hypot(px.path.se, t * px.object.ambient.se)};
    return px;
}

}  // namespace host

namespace {
constexpr const char* usage = R"(usage: embed_host [options]
  --map-photons N   photons whose scattering events are stored (default 5e5)
  --radius R        collection radius in m, below 0.5 (default 0.05)
  --size N          image height in pixels, >= 2 (default 128; the image is 3:2)
  --threads N       (default 2)
  --out PREFIX      writes PREFIX.exr and PREFIX.png (default "embed_host")
A host ray tracer's own objects in secchi's water. It checks the embedding contract on the
image it renders and exits with status 1 if a check fails.
)";

double seconds_since(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}
}  // namespace

int main(int argc, char** argv) {
    using namespace secchi;
    return run_program(argc, argv, "embed_host", usage, [&] {
        const CommandLine cl(argc, argv, {"map-photons", "radius", "size", "threads", "out"});
        const auto threads = cl.threads(2);
        const int height = static_cast<int>(cl.count("size", 128, 2, 8192)), width = height * 3 / 2;
        const std::string out = cl.text("out", "embed_host");
        OutputFile exr_file("--out", out + ".exr"), png_file("--out", out + ".png");  // checked before the work
        const auto t0 = std::chrono::steady_clock::now();

        // ---- secchi: the water and its photon map, built once ---------------------------------
        // Clear coastal water (a = 0.06, b = 0.12 /m: c = 0.18 /m, w0 = 0.67) with Petzold's
        // particle phase function, over a Lambertian bottom of albedo 0.25 at 8 m; flat surface
        // (n = 1.34), the sun at 30 deg from the zenith (E_perp = 1) and a uniform sky of plane
        // irradiance 0.2. The map is a periodic section 1 m wide (PlaneParallelConfig's default):
        // the host's coordinates may lie anywhere, the water is horizontally homogeneous.
        const double bottom_depth = 8.0;
        const auto water = HomogeneousWater<TabulatedPhase>(0.06, 0.12, petzold_m93());
        PlaneParallelConfig cfg;
        cfg.sun_zenith_deg = 30.0;
        cfg.sky_irradiance = 0.2;
        cfg.bottom = Bottom::lambertian_at(bottom_depth, 0.25);
        cfg.transport.photons = cfg.transport.map_photons = cl.count("map-photons", 500'000);
        cfg.transport.threads = threads;
        const Radius radius(cl.number("radius", 0.05));
        require(radius.value() < 0.5 * cfg.section_width, "--radius", radius.value(), "must be < 0.5 m (half the map's section)");
        // The map owns the photons and must outlive the estimator, which refers to it.
        const auto mapped = trace_photon_map<VoiGridStore<CompactRecord>>(water, cfg, radius);
        // The collection cone of 0.005 sr: the scattering within it counts as unscattered, so
        // the ray's transmittance is exp(-c' t) with c' = c - b f, f Petzold's share in the cone.
        const ConeAveragedPhase cone(water.phase(), 0.005, ConePeak::transmitted, cone_table(cfg));
        const HomogeneousRayOptics optics(cone, water.attenuation(), water.scattering());
        const RadianceEstimator est(mapped.map, VoiCylinder(0.0, bottom_depth), optics, radius);
        std::printf("map: %zu scattering events stored in %.1f s\n", mapped.map.store().records().size(), seconds_since(t0));

        // ---- the host's scene, and the ambient light secchi gives it ---------------------------
        const host::Scene scene = host::demo_scene();
        const auto [top, bottom] = scene.depth_range();
        require(top > 0.0 && bottom <= bottom_depth, "host objects' top depth (m)", top,
                "must lie in the water: the objects between the surface and the bottom");
        const auto t1 = std::chrono::steady_clock::now();
        const host::AmbientTable ambient(est, top, bottom, 1.5, threads);
        std::printf("ambient light: %zu depths in %.1f s\n", ambient.depths().size(), seconds_since(t1));
        std::printf("  depth (m)   Ed diffuse         Eu   (W m^-2 nm^-1 per unit E_perp)\n");
        for (std::size_t i = 0; i < ambient.depths().size(); ++i)
            std::printf("  %6.2f   %.4f +- %.4f  %.4f +- %.4f\n", ambient.depths()[i], ambient.ed_diffuse()[i].value,
                        ambient.ed_diffuse()[i].se, ambient.eu()[i].value, ambient.eu()[i].se);

        // ---- the host's render: rows on the host's own threads ---------------------------------
        // 5 m deep, looking along +y and 6 deg up, 76 deg vertical field of view: the sun shines
        // from the image's left (+x); Snell's window (above 41.4 deg of elevation) tops the image.
        const host::Camera camera({0.0, 0.0, 5.0}, {0.0, std::cos(6.0 * deg), -std::sin(6.0 * deg)}, 76.0, width, height);
        Image image(width, height);
        std::vector<float>& value = image.add_channel("L");
        std::vector<float>& se = image.add_channel("L.se");
        // What each pixel sees, for the self-check: 0 open water, 1 a sunlit object, 2 an object in shade.
        std::vector<unsigned char> kind(image.pixels(), 0);
        std::atomic<int> object_pixels{0}, shadowed_pixels{0};
        const auto t2 = std::chrono::steady_clock::now();
        host::for_each_row(height, threads, [&](int y) {
            for (int x = 0; x < width; ++x) {
                const host::Pixel px = host::trace_pixel(scene, est, ambient, camera, x, y);
                const std::size_t i = static_cast<std::size_t>(y) * width + x;
                value[i] = static_cast<float>(px.radiance.value);
                se[i] = static_cast<float>(px.radiance.se);
                if (px.hit) {
                    kind[i] = px.object.sun > 0.0 ? 1 : 2;
                    ++object_pixels;
                    shadowed_pixels += px.object.shadowed;
                }
            }
        });
        for (const char* c : {"R", "G", "B"}) image.add_channel(c) = value;  // one band: grey
        const double render_seconds = seconds_since(t2);
        write_exr(image, exr_file.partial_path());
        const double white = write_png_preview(image, "L", png_file.partial_path());
        exr_file.commit();
        png_file.commit();
        std::printf("image: %d x %d in %.1f s; %d pixels see an object, %d of them in the host's shadows\n", width, height,
                    render_seconds, object_pixels.load(), shadowed_pixels.load());
        std::printf("wrote %s.exr (L, L.se, R, G, B in W m^-2 sr^-1 nm^-1 per unit E_perp) and %s.png (white = %.4g)\n",
                    out.c_str(), out.c_str(), white);

        // ---- self-check: the embedding contract, on the rendered image --------------------------
        int failures = 0;
        const auto check = [&](bool ok, const char* what) {
            std::printf("check: %-72s %s\n", what, ok ? "ok" : "FAILED");
            failures += !ok;
        };
        bool finite = true;
        for (std::size_t i = 0; i < value.size(); ++i)
            finite = finite && std::isfinite(value[i]) && value[i] >= 0.0f && std::isfinite(se[i]) && se[i] >= 0.0f;
        check(finite, "every pixel's radiance and SE finite and >= 0");

        // The host's shadow ray runs towards the sun, against the beam's direction: the crate's
        // top beneath the diver's torso along the beam is in shadow, its far corner is lit.
        {
            const host::Sphere& torso = scene.spheres[1];
            const host::Box& crate = scene.boxes[0];
            const host::Vec beam = host::from_secchi(est.direct_sun(host::to_secchi(torso.centre)).direction);
            const double s = (crate.lo.z - torso.centre.z) / beam.z;
            const host::Hit under{0.0, torso.centre + s * beam, {0.0, 0.0, -1.0}, crate.albedo};
            const host::Hit corner{0.0, {crate.lo.x + 0.1, crate.hi.y - 0.1, crate.lo.z}, {0.0, 0.0, -1.0}, crate.albedo};
            const host::ObjectRadiance in_shadow = host::shade(scene, est, ambient, under);
            const host::ObjectRadiance in_sun = host::shade(scene, est, ambient, corner);
            check(in_shadow.shadowed && in_shadow.sun == 0.0 && !in_sun.shadowed && in_sun.sun > 0.0,
                  "crate top: shadowed beneath the diver along the sun's beam, lit beyond");
        }

        // The first pixel in row order that sees open water, and the first that sees a sunlit object.
        int open_x = -1, open_y = -1, hit_x = -1, hit_y = -1;
        for (std::size_t i = 0; i < kind.size(); ++i) {
            const int x = static_cast<int>(i % width), y = static_cast<int>(i / width);
            if (kind[i] == 0 && open_x < 0) open_x = x, open_y = y;
            if (kind[i] == 1 && hit_x < 0) hit_x = x, hit_y = y;
        }
        check(open_x >= 0 && hit_x >= 0, "the image shows open water and a sunlit object");
        if (open_x >= 0) {
            // Open water: the pixel is est.radiance() of its unbounded ray, bit for bit.
            const Ray ray{host::to_secchi(camera.position()), host::to_secchi(camera.direction(open_x, open_y)), INFINITY};
            const Estimate l = est.radiance(ray, 0);
            const std::size_t i = static_cast<std::size_t>(open_y) * width + open_x;
            std::printf("open water, pixel (%d, %d): image %.7g, est.radiance %.7g +- %.2g\n", open_x, open_y, value[i],
                        l.value, l.se);
            check(value[i] == static_cast<float>(l.value) && se[i] == static_cast<float>(l.se),
                  "open-water pixel == est.radiance(unbounded ray)");
        }
        if (hit_x >= 0) {
            // On an object: the pixel is the path radiance up to the object plus T times the
            // object's radiance, recomputed here call by call.
            const host::Vec o = camera.position(), d = camera.direction(hit_x, hit_y);
            const auto hit = scene.intersect(o, d, 0.0, INFINITY);
            const Ray to_object{host::to_secchi(o), host::to_secchi(d), hit->t};
            const Estimate path = est.radiance(to_object, 0);
            const double t = est.transmittance(to_object);
            const host::ObjectRadiance obj = host::shade(scene, est, ambient, *hit);
            const std::size_t i = static_cast<std::size_t>(hit_y) * width + hit_x;
            const double expected = path.value + t * obj.value();
            std::printf("object, pixel (%d, %d) at %.3f m: image %.7g = path %.6g + T %.6g x object %.6g "
                        "(sun %.4g + ambient %.4g)\n",
                        hit_x, hit_y, hit->t, value[i], path.value, t, obj.value(), obj.sun, obj.ambient.value);
            check(std::abs(value[i] - expected) <= 1e-6 * expected, "object pixel == path(t) + T(t) x object radiance");
            check(t > 0.0 && t < 1.0 && std::abs(t - std::exp(-optics.attenuation * hit->t)) <= 1e-9 * t,
                  "T(t) == exp(-c' t), the optics' attenuation");
            // What the composition rests on: radiance() with t_max = t is the path radiance up to
            // t only, so the path to t plus T(t) times all the ray sees from t onward is the
            // unobstructed ray's radiance (exactly, up to rounding, for a ray that reaches the
            // surface or the bottom before its transmittance falls to
            // RadianceSettings::ray_transmittance, as this upward ray does).
            const Estimate whole = est.radiance(Ray{to_object.origin, to_object.direction, INFINITY}, 0);
            const Estimate beyond = est.radiance(Ray{host::to_secchi(hit->point), to_object.direction, INFINITY}, 0);
            const double joined = path.value + t * beyond.value;
            std::printf("composition: path(0, t) %.6g + T(t) x L(t onward) %.6g = %.9g; L(whole ray) = %.9g\n",
                        path.value, beyond.value, joined, whole.value);
            check(std::abs(joined - whole.value) <= 1e-9 * whole.value, "path(0, t) + T(t) L(t onward) == L(whole ray)");
        }
        std::printf("total %.1f s\n", seconds_since(t0));
        if (failures) {
            std::printf("self-check: %d failed\n", failures);
            return 1;
        }
        std::printf("self-check: all passed\n");
        return 0;
    });
}
