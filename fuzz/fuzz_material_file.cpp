// libFuzzer target: the material-file reader (io/material_file.hpp) and the medium builder
// behind it (io/material_medium.hpp, optics/iop/linear_model.hpp's stratify).
//
// Input: the bytes up to the first NUL are a material file, the bytes after it a data file
// "data.txt" beside it (what FILENAME = data.txt names: spectral coefficients or a phase
// table). Both are written to a scratch folder and read as files, like the programs read them.
// The data file is also read alone by read_spectral_file.
//
// Checked: every rejection is a secchi::input_error. Any other exception (uncaught: abort),
// a crash, a sanitizer report, a hang or a model that binds but samples to a non-finite or
// negative coefficient is a finding.
#include "secchi/core/error.hpp"
#include "secchi/io/material_file.hpp"
#include "secchi/io/material_medium.hpp"
#include "secchi/optics/iop/linear_model.hpp"
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>
#include <unistd.h>

namespace {

namespace fs = std::filesystem;

/// A scratch folder of this process under $TMPDIR (or /tmp), removed at exit.
struct Scratch {
    fs::path dir;
    Scratch() {
        const char* tmp = std::getenv("TMPDIR");
        std::string pattern = std::string(tmp && *tmp ? tmp : "/tmp") + "/secchi-fuzz-material-XXXXXX";
        if (!mkdtemp(pattern.data())) {
            std::perror("mkdtemp");
            std::abort();
        }
        dir = pattern;
    }
    ~Scratch() {
        std::error_code ec;
        fs::remove_all(dir, ec);
    }
};

const fs::path& scratch() {
    static const Scratch s;
    return s.dir;
}

void write_file(const fs::path& path, std::string_view bytes) {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace secchi;
    const std::string_view bytes(reinterpret_cast<const char*>(data), size);
    const std::size_t nul = bytes.find('\0');
    const fs::path material = scratch() / "fuzz.mat", table = scratch() / "data.txt";
    write_file(material, bytes.substr(0, nul));
    write_file(table, nul == std::string_view::npos ? std::string_view() : bytes.substr(nul + 1));

    try {
        (void)io::read_spectral_file(table);
    } catch (const input_error&) {
    }
    try {
        const io::MaterialSection root = io::read_material_file(material);
        const iop::RuntimeIopModel model = io::bind_iop_model(root, /*seed=*/1);
        static const std::vector<double> depths = iop::uniform_depths(/*max_depth=*/20.0, /*spacing=*/2.0);
        for (const double wl : {400.0, 550.0, 700.0}) {
            const auto water = iop::stratify(model, wl, depths);  // rejects non-finite or negative a, b_i
            for (const double z : depths)
                for (auto k : {Coefficient::absorption, Coefficient::scattering, Coefficient::attenuation}) {
                    const double v = water.coefficient(k, z);
                    if (!(std::isfinite(v) && v >= 0.0)) {
                        std::fprintf(stderr, "coefficient %d at z = %g, %g nm is %g\n", static_cast<int>(k), z, wl, v);
                        std::abort();
                    }
                }
        }
    } catch (const input_error&) {
    }
    return 0;
}
