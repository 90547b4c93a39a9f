#!/usr/bin/env python3
"""Bad-input battery: every program, every kind of bad argument or input file.

Each case must exit with status 2 within the time limit, print exactly one line on stderr,
"<program>: invalid ..." naming every string of its `names` (the parameter and the value, and
file:line for a file's contents), and leave none of its output paths (nor a PATH.partial.<token>) behind.

usage: bad_input_battery.py BIN_DIR=<dir> ... (see main); run by ctest (tests/CMakeLists.txt).
Add a case: one row in CASES, (program, arguments, names that the message must contain, outputs).
In the arguments and names, {tmp} is a scratch folder holding the fixtures made by fixtures(),
{mat} the examples' materials folder.
"""
import os
import shutil
import subprocess
import sys
import tempfile

TIMEOUT_S = 10  # a rejected case answers in milliseconds; this only catches hangs

# Options shared by the programs that take them: (arguments, names in the message).
THREADS = [
    ("--threads 0", ["--threads", "0"]),
    ("--threads -1", ["--threads", "-1"]),
    ("--threads 1x", ["--threads", "1x"]),
    ("--threads ''", ["--threads"]),
    ("--threads 0x10", ["--threads", "0x10"]),
    ("--threads nan", ["--threads", "nan"]),
    ("--threads inf", ["--threads", "inf"]),
    ("--threads 1e999", ["--threads", "1e999"]),
    ("--threads 1e6", ["--threads", "1e6"]),
    ("--threads 1 --threads 2", ["--threads", "more than once"]),
    ("--threads", ["--threads", "needs a value"]),
]
COMMON = [
    ("--bogus 1", ["--bogus", "unknown option"]),
    ("--Threads 2", ["--Threads", "unknown option"]),
    ("stray", ["stray"]),
    ("--quiet --quiet", ["--quiet", "more than once"]),
]

# (program, arguments, names the message must contain, output paths that must not exist after)
CASES = [
    # ---- slab ---------------------------------------------------------------------------
    ("slab", "--albedo -0.1", ["albedo", "-0.1"], []),
    ("slab", "--albedo 1.5", ["albedo", "1.5"], []),
    ("slab", "--albedo nan", ["--albedo", "nan"], []),
    ("slab", "--albedo -inf", ["--albedo", "-inf"], []),
    ("slab", "--albedo 1e999", ["--albedo", "1e999"], []),
    ("slab", "--albedo 0.9x", ["--albedo", "0.9x"], []),
    ("slab", "--albedo ''", ["--albedo"], []),
    ("slab", "--phase hg:1", ["g = 1", "|g| < 1"], []),
    ("slab", "--phase hg:-1.5", ["g = -1.5"], []),
    ("slab", "--phase hg:nan", ["g = nan"], []),
    ("slab", "--phase bogus", ["phase", "bogus"], []),
    ("slab", "--phase ff:-1", ["bb_over_b = -1"], []),
    ("slab", "--sun-zenith -5", ["sun", "-5"], []),
    ("slab", "--sun-zenith 95", ["sun", "95"], []),
    ("slab", "--sun-zenith inf", ["--sun-zenith", "inf"], []),
    ("slab", "--water-index 0", ["index", "0"], []),
    ("slab", "--sky -1", ["sky", "-1"], []),
    ("slab", "--depths -1", ["depth", "-1"], []),
    ("slab", "--depths 1,,5", ["--depths"], []),
    ("slab", "--depths 1,inf", ["--depths", "inf"], []),
    ("slab", "--depths ''", ["--depths"], []),
    ("slab", "--photons 0", ["photons", "0"], []),
    ("slab", "--photons -5", ["--photons", "-5"], []),
    ("slab", "--photons 2.5", ["--photons", "2.5"], []),
    ("slab", "--photons 0x10", ["--photons", "0x10"], []),
    ("slab", "--photons 1e999", ["--photons", "1e999"], []),
    ("slab", "--photons 1e19", ["--photons", "1e19"], []),
    ("slab", "--photons 1e18 --map-photons 1e18", ["photons", "1000000000000000000", "memory"], []),
    ("slab", "--photons 1e15", ["photons", "1000000000000000", "memory"], []),
    ("slab", "--map-photons 2000 --photons 1000", ["map photons", "2000"], []),
    ("slab", "--batches 0", ["batches", "0"], []),
    ("slab", "--batches 1e6", ["batches"], []),
    ("slab", "--batches 6e9", ["--batches", "6e9"], []),
    ("slab", "--steps 4294967296", ["--steps", "4294967296"], []),
    ("slab", "--ray-grid 1e10", ["--ray-grid", "1e10"], []),
    ("slab", "--seed -1", ["--seed", "-1"], []),
    ("slab", "--radius 0", ["radius", "0"], []),
    ("slab", "--radius -1", ["radius", "-1"], []),
    ("slab", "--radius nan", ["--radius", "nan"], []),
    ("slab", "--steps 0", ["steps", "0"], []),
    ("slab", "--omega 0", ["omega", "0"], []),
    ("slab", "--omega -1", ["omega", "-1"], []),
    ("slab", "--ray-transmittance 2", ["ray transmittance", "2"], []),
    ("slab", "--ray-grid 0", ["ray", "0"], []),
    ("slab", "--section-width 0", ["section", "0"], []),
    ("slab", "--bottom-depth -1", ["bottom", "-1"], []),
    ("slab", "--bottom-depth 5 --bottom-albedo 1.5", ["albedo", "1.5"], []),
    ("slab", "--bottom-albedo 0.5", ["--bottom-albedo", "needs --bottom-depth"], []),
    ("slab", "--wind -3", ["wind", "-3"], []),
    ("slab", "--wind nan", ["--wind", "nan"], []),
    ("slab", "--wind 5 --slope-variance 0.03", ["--slope-variance", "conflicts"], []),
    ("slab", "--store octree", ["store", "octree"], []),
    ("slab", "--tracer simd", ["tracer", "simd"], []),
    ("slab", "--absorption none", ["absorption", "none"], []),
    ("slab", "--source moon", ["source", "moon"], []),
    ("slab", "--facets weighted", ["facets", "weighted"], []),
    ("slab", "--shadowing partial", ["shadowing", "partial"], []),
    ("slab", "--facets redraw", ["--facets", "needs --wind or --slope-variance"], []),
    ("slab", "--shadowing smith", ["--shadowing", "needs --wind or --slope-variance"], []),
    ("slab", "--upward-lobe 0.5", ["--upward-lobe", "needs --upward-importance"], []),
    ("slab", "--cone-peak sharp", ["cone", "sharp"], []),
    ("slab", "--source atmosphere --aerosol-g 1", ["aerosol", "1"], []),
    ("slab", "--source atmosphere --aerosol-albedo 1.5", ["aerosol", "1.5"], []),
    ("slab", "--source parametric-sky --direct -1", ["direct", "-1"], []),
    ("slab", "--aerosol-g 0.5", ["--aerosol-g", "needs --source atmosphere"], []),
    ("slab", "--json {tmp}/dir", ["--json", "{tmp}/dir", "folder"], []),
    ("slab", "--json {tmp}/no/such/out.json", ["--json", "{tmp}/no/such/out.json"], ["{tmp}/no/such/out.json"]),
    ("slab", "--json ''", ["--json", "must name a file"], []),
    ("slab", "--json /proc/slab.json", ["--json", "/proc/slab.json"], ["/proc/slab.json"]),
    ("slab", "--json {tmp}/slab.json --albedo 2", ["albedo", "2"], ["{tmp}/slab.json"]),
    ("slab", "--json {tmp}/slab.json --photons 1e18 --map-photons 1e18", ["photons", "memory"], ["{tmp}/slab.json"]),
    # ---- iop_profile --------------------------------------------------------------------
    ("iop_profile", "", ["medium", "--material", "--problem3"], []),
    ("iop_profile", "--material {tmp}/missing.mat", ["material file", "{tmp}/missing.mat"], []),
    ("iop_profile", "--material {tmp}/empty.mat", ["{tmp}/empty.mat"], []),
    ("iop_profile", "--material {tmp}/binary.mat", ["{tmp}/binary.mat:"], []),
    ("iop_profile", "--material {tmp}/dir", ["{tmp}/dir"], []),
    ("iop_profile", "--material {tmp}/bad_type.mat", ["{tmp}/bad_type.mat:5", "bogus"], []),
    ("iop_profile", "--material {tmp}/bad_number.mat", ["{tmp}/bad_number.mat:6", "1x"], []),
    ("iop_profile", "--material {tmp}/nan_number.mat", ["{tmp}/nan_number.mat:6", "nan"], []),
    ("iop_profile", "--material {mat}/case1_chlorophyll.mat --material-entry nope", ["nope"], []),
    ("iop_profile", "--problem3 --material {mat}/case1_chlorophyll.mat", ["--material", "--problem3"], []),
    ("iop_profile", "--problem3 --wavelengths 700:400:10", ["--wavelengths", "700:400:10"], []),
    ("iop_profile", "--problem3 --wavelengths 400:700:0", ["--wavelengths", "400:700:0"], []),
    ("iop_profile", "--problem3 --wavelengths nan", ["--wavelengths", "nan"], []),
    ("iop_profile", "--problem3 --wavelengths 1e999", ["--wavelengths", "1e999"], []),
    ("iop_profile", "--problem3 --wavelengths 400:700:1e-6", ["--wavelengths", "400:700:1e-6"], []),
    ("iop_profile", "--problem3 --wavelengths 400:700:0.001 --depths 0:60:0.001", ["--wavelengths", "million"], []),
    ("iop_profile", "--problem3 --depths -5", ["--depths", "-5"], []),
    ("iop_profile", "--problem3 --depths 0:x:5", ["--depths", "0:x:5"], []),
    ("iop_profile", "--problem3 --depths 0:60:5:1", ["--depths", "0:60:5:1"], []),
    ("iop_profile", "--material {mat}/case1_chlorophyll.mat --wavelengths 750", ["750"], []),
    ("iop_profile", "--material {mat}/case1_chlorophyll.mat --seed -2", ["--seed", "-2"], []),
    ("iop_profile", "--problem3 --out {tmp}/dir", ["--out", "{tmp}/dir"], []),
    ("iop_profile", "--problem3 --out {tmp}/no/such/p.csv", ["--out", "{tmp}/no/such/p.csv"], ["{tmp}/no/such/p.csv"]),
    ("iop_profile", "--problem3 --out /proc/p.csv", ["--out", "/proc/p.csv"], []),
    ("iop_profile", "--material {tmp}/bad_type.mat --out {tmp}/iop.csv", ["bad_type.mat:5"], ["{tmp}/iop.csv"]),
    ("iop_profile", "--material {mat}/pspurewater.mat --wavelengths 300:800:50 --out {tmp}/iop2.csv", ["wavelength"], ["{tmp}/iop2.csv"]),
    # ---- natural_water (MATERIAL_FILE [ENTRY]) ------------------------------------------
    ("natural_water", "{tmp}/missing.mat", ["{tmp}/missing.mat"], []),
    ("natural_water", "{tmp}/empty.mat", ["{tmp}/empty.mat"], []),
    ("natural_water", "{tmp}/binary.mat", ["{tmp}/binary.mat:"], []),
    ("natural_water", "{tmp}/dir", ["{tmp}/dir"], []),
    ("natural_water", "{tmp}/bad_type.mat", ["{tmp}/bad_type.mat:5", "bogus"], []),
    ("natural_water", "{mat}/case1_chlorophyll.mat nope", ["nope"], []),
    ("natural_water", "{mat}/case1_chlorophyll.mat a b", ["b", "too many"], []),
    ("natural_water", "--bogus", ["--bogus", "unknown option"], []),
    # ---- kirk_aop -----------------------------------------------------------------------
    ("kirk_aop", "--photons 0", ["photons", "0"], []),
    ("kirk_aop", "--photons -1", ["--photons", "-1"], []),
    ("kirk_aop", "--photons nan", ["--photons", "nan"], []),
    ("kirk_aop", "--photons 1e18", ["photons", "memory"], []),
    ("kirk_aop", "--photons 10", ["photons", "10"], []),
    # ---- spectral_case1 -----------------------------------------------------------------
    ("spectral_case1", "--material {tmp}/missing.mat --csv {tmp}/s.csv", ["{tmp}/missing.mat"], ["{tmp}/s.csv"]),
    ("spectral_case1", "--material {tmp}/binary.mat --csv {tmp}/s.csv", ["{tmp}/binary.mat:"], ["{tmp}/s.csv"]),
    ("spectral_case1", "--material {tmp}/dir --csv {tmp}/s.csv", ["{tmp}/dir"], ["{tmp}/s.csv"]),
    ("spectral_case1", "--material {tmp}/empty.mat --csv {tmp}/s.csv", ["{tmp}/empty.mat"], ["{tmp}/s.csv"]),
    ("spectral_case1", "--material {mat}/case1_chlorophyll.mat --wavelengths 750 --csv {tmp}/s.csv", ["750"], ["{tmp}/s.csv"]),
    ("spectral_case1", "--material {mat}/case1_chlorophyll.mat --wavelengths 400:700:0.5", ["--wavelengths", "256"], []),
    ("spectral_case1", "--material {mat}/case1_chlorophyll.mat --depths -1 --csv {tmp}/s.csv", ["depth", "-1"], ["{tmp}/s.csv"]),
    ("spectral_case1", "--material {mat}/case1_chlorophyll.mat --photons 0", ["--photons", "0"], []),
    ("spectral_case1", "--material {mat}/case1_chlorophyll.mat --photons 1e18 --csv {tmp}/s.csv", ["photons", "memory"], ["{tmp}/s.csv"]),
    ("spectral_case1", "--material {mat}/case1_chlorophyll.mat --csv {tmp}/dir", ["--csv", "{tmp}/dir"], []),
    ("spectral_case1", "--material {mat}/case1_chlorophyll.mat --csv {tmp}/no/such/s.csv", ["--csv"], ["{tmp}/no/such/s.csv"]),
    ("spectral_case1", "--material {mat}/case1_chlorophyll.mat --csv ''", ["--csv", "must name a file"], []),
    # ---- underwater_camera --------------------------------------------------------------
    ("underwater_camera", "--size 0", ["--size", "0"], []),
    ("underwater_camera", "--size 1e6", ["--size", "1e6"], []),
    ("underwater_camera", "--size 1e999", ["--size", "1e999"], []),
    ("underwater_camera", "--spp 0", ["--spp", "0"], []),
    ("underwater_camera", "--spp 1e9", ["--spp", "1e9"], []),
    ("underwater_camera", "--map-photons 0 --out {tmp}/cam_", ["photons", "0"], ["{tmp}/cam_up.exr", "{tmp}/cam_up.png"]),
    ("underwater_camera", "--map-photons -3", ["--map-photons", "-3"], []),
    ("underwater_camera", "--map-photons 1e18 --out {tmp}/cam_", ["photons", "memory"], ["{tmp}/cam_up.exr", "{tmp}/cam_distribution.png"]),
    ("underwater_camera", "--out {tmp}/no/such/cam_", ["--out", "{tmp}/no/such/cam_"], []),
    ("underwater_camera", "--out {tmp}/empty.mat/cam_", ["--out", "{tmp}/empty.mat/cam_"], []),
    ("underwater_camera", "--out /proc/cam_", ["--out", "/proc/cam_"], []),
    # ---- littoral_scenes ----------------------------------------------------------------
    ("littoral_scenes", "--size 0", ["--size", "0"], []),
    ("littoral_scenes", "--size 1e999", ["--size", "1e999"], []),
    ("littoral_scenes", "--spp 0", ["--spp", "0"], []),
    ("littoral_scenes", "--spp 1e9", ["--spp", "1e9"], []),
    ("littoral_scenes", "--photons 10", ["--photons", "10"], []),
    ("littoral_scenes", "--photons nan", ["--photons", "nan"], []),
    ("littoral_scenes", "--photons -2e6", ["--photons", "-2e6"], []),
    ("littoral_scenes", "--photons 1e18", ["--photons", "1e18"], []),
    ("littoral_scenes", "--photons 1e10 --out {tmp}/lit_", ["photons", "memory"], ["{tmp}/lit_caustics_view.exr", "{tmp}/lit_baffle_detector.png"]),
    ("littoral_scenes", "--out {tmp}/no/such/lit_", ["--out", "{tmp}/no/such/lit_"], []),
    ("littoral_scenes", "--out {tmp}/empty.mat/lit_", ["--out", "{tmp}/empty.mat/lit_"], []),
    ("littoral_scenes", "--out /proc/lit_", ["--out", "/proc/lit_"], []),
    # ---- embed_host ---------------------------------------------------------------------
    ("embed_host", "--radius 0.5", ["--radius", "0.5"], []),
    ("embed_host", "--radius -1", ["radius", "-1"], []),
    ("embed_host", "--radius nan", ["--radius", "nan"], []),
    ("embed_host", "--size 1", ["--size", "1"], []),
    ("embed_host", "--size 1e6", ["--size", "1e6"], []),
    ("embed_host", "--map-photons -5", ["--map-photons", "-5"], []),
    ("embed_host", "--map-photons 0 --out {tmp}/host", ["photons", "0"], ["{tmp}/host.exr", "{tmp}/host.png"]),
    ("embed_host", "--map-photons 1e18 --out {tmp}/host", ["photons", "memory"], ["{tmp}/host.exr", "{tmp}/host.png"]),
    ("embed_host", "--out {tmp}/empty.mat/host", ["--out", "{tmp}/empty.mat/host.exr"], []),
    ("embed_host", "--out {tmp}/no/such/host", ["--out", "{tmp}/no/such/host"], []),
    # ---- canonical ----------------------------------------------------------------------
    ("canonical", "--store voi", ["--problem", "required"], []),
    ("canonical", "--problem 9z --store voi", ["--problem", "9z"], []),
    ("canonical", "--problem '' --store voi", ["--problem"], []),
    ("canonical", "--problem 1a", ["--store", "required"], []),
    ("canonical", "--problem 1a --store octree", ["store", "octree"], []),
    ("canonical", "--problem 1a --store voi --photons 0", ["photons", "0"], []),
    ("canonical", "--problem 1a --store voi --photons 1e18", ["photons", "memory"], []),
    ("canonical", "--problem 1a --store voi --photons 1x", ["--photons", "1x"], []),
    ("canonical", "--problem 1a --store voi --seed nan", ["--seed", "nan"], []),
    ("canonical", "--problem 1a --store voi --budget-scale 0", ["--budget-scale", "0"], []),
    ("canonical", "--problem 1a --store voi --budget-scale nan", ["--budget-scale", "nan"], []),
    ("canonical", "--problem 1a --store voi --budget-scale 1e9", ["--budget-scale", "1e9"], []),
    ("canonical", "--problem 1a --store voi --tracer simd", ["tracer", "simd"], []),
    ("canonical", "--problem 5 --store voi --facets weighted", ["facets", "weighted"], []),
    ("canonical", "--problem all --store voi --petzold bogus", ["petzold", "bogus"], []),
    ("canonical", "--problem all --store voi --importance-cosine 2", ["importance", "2"], []),
    ("canonical", "--problem all --store voi --importance-cosine nan", ["--importance-cosine", "nan"], []),
    ("canonical", "--problem all --store voi --aerosol-g 1", ["aerosol", "1"], []),
    ("canonical", "--problem all --store voi --aerosol-albedo -0.5", ["aerosol", "-0.5"], []),
    ("canonical", "--problem all --store voi --aerosol-scale-height 0", ["scale height", "0"], []),
    ("canonical", "--problem all --store voi --material {tmp}/binary.mat", ["{tmp}/binary.mat:"], []),
    ("canonical", "--problem all --store voi --material {tmp}/missing.mat", ["{tmp}/missing.mat"], []),
    ("canonical", "--problem all --store voi --material {tmp}/bad_type.mat", ["{tmp}/bad_type.mat:5"], []),
    ("canonical", "--problem 1a --store voi --json {tmp}/dir", ["--json", "{tmp}/dir"], []),
    ("canonical", "--problem 1a --store voi --json {tmp}/no/such/c.json", ["--json"], ["{tmp}/no/such/c.json"]),
    ("canonical", "--problem 2a --store voi --json {tmp}/c.json --exr {tmp}/dir", ["--exr", "{tmp}/dir"], ["{tmp}/c.json"]),
    ("canonical", "--problem 3 --store voi --json {tmp}/c.json --profile-csv {tmp}/no/p.csv", ["--profile-csv"], ["{tmp}/c.json"]),
    # An option that would change none of the problems run.
    ("canonical", "--problem 1a --store voi --json {tmp}/c.json --exr {tmp}/m.exr", ["--exr", "only problem 2a", "--problem 1a"],
     ["{tmp}/c.json", "{tmp}/m.exr"]),
    ("canonical", "--problem 1a,2a --store voi --material {tmp}/bad_type.mat", ["--material", "only problem 3", "1a,2a"], []),
    ("canonical", "--problem 1b --store voi --petzold petzold-linear", ["--petzold", "problems 2a, 2b, 3, 4, 5 or 6"], []),
    ("canonical", "--problem 2a --store voi --facets redraw", ["--facets", "only problem 5"], []),
    ("canonical", "--problem kirk --aerosol-g 0.5", ["--aerosol-g", "only problem 4"], []),
    ("canonical", "--problem kirk --budget-scale 2", ["--budget-scale", "--problem kirk does not include"], []),
    ("canonical", "--problem kirk --store voi", ["--store", "--problem kirk does not include"], []),
    ("canonical", "--problem 1a --store voi --upward-lobe 0.5", ["--upward-lobe", "needs --upward-importance"], []),
    ("canonical", "--problem 1a --store voi --photons 0 --json {tmp}/c.json", ["photons", "0"], ["{tmp}/c.json", "{tmp}/photon_map_2a.exr"]),
]

THREADED = ["slab", "kirk_aop", "spectral_case1", "underwater_camera", "littoral_scenes", "embed_host", "canonical"]
PREFIX = {  # arguments a program needs before a shared case reaches the option under test
    "canonical": "--problem 1a --store voi",
    "spectral_case1": "--material {mat}/case1_chlorophyll.mat",
}
for program in THREADED:
    CASES += [(program, PREFIX.get(program, "") + " " + args, names, []) for args, names in THREADS]
for program in ["slab", "iop_profile", "kirk_aop", "spectral_case1", "underwater_camera", "littoral_scenes", "embed_host",
                "canonical"]:
    CASES += [(program, PREFIX.get(program, "") + " " + args, names, []) for args, names in COMMON]


def fixtures(tmp):
    os.makedirs(os.path.join(tmp, "dir"))
    open(os.path.join(tmp, "empty.mat"), "w").close()
    with open(os.path.join(tmp, "binary.mat"), "wb") as f:
        f.write(bytes(range(256)) * 4 + b"\x00\xff\xfe" * 100)
    body = "BULK_PROPERTIES {{\n  IOP_MODEL {{\n    BASE_MEDIUM = purewater\n    ADD_ABSORPTION_MODEL {{\n{}\n    }}\n  }}\n}}\n"
    with open(os.path.join(tmp, "bad_type.mat"), "w") as f:
        f.write(body.format("      TYPE = bogus"))
    with open(os.path.join(tmp, "bad_number.mat"), "w") as f:
        f.write(body.format("      TYPE = constant\n      ABS = 1x"))
    with open(os.path.join(tmp, "nan_number.mat"), "w") as f:
        f.write(body.format("      TYPE = constant\n      ABS = nan"))


def split(args):
    import shlex
    return shlex.split(args)


def main():
    bins = {k: os.path.abspath(v) for k, v in (a.split("=", 1) for a in sys.argv[1:] if "=" in a)}
    materials = bins.pop("materials")
    tmp = tempfile.mkdtemp(prefix="secchi_battery_")
    failures = []
    try:
        fixtures(tmp)
        programs = set()
        for program, args, names, outputs in CASES:
            fill = lambda s: s.replace("{tmp}", tmp).replace("{mat}", materials)
            argv = [bins[program]] + split(fill(args))
            shown = program + " " + args
            programs.add(program)
            env = dict(os.environ)
            env.pop("SECCHI_PROGRESS", None)
            try:
                p = subprocess.run(argv, capture_output=True, timeout=TIMEOUT_S, env=env, cwd=tmp)
            except subprocess.TimeoutExpired:
                failures.append(f"{shown}: no answer within {TIMEOUT_S} s")
                continue
            err = p.stderr.decode(errors="replace")
            lines = [l for l in err.splitlines() if l.strip()]
            problems = []
            if p.returncode != 2:
                problems.append(f"status {p.returncode}")
            if len(lines) != 1:
                problems.append(f"{len(lines)} lines on stderr")
            elif not lines[0].startswith(program + ": invalid "):
                problems.append("message does not start with '" + program + ": invalid '")
            for name in names:
                if fill(name) not in err:
                    problems.append(f"message does not name '{fill(name)}'")
            for out in outputs:
                if os.path.exists(fill(out)):
                    problems.append(f"left {fill(out)} behind")
                    os.remove(fill(out))
            for leftover in os.listdir(tmp):
                if ".partial" in leftover:
                    problems.append(f"left {leftover} behind")
                    os.remove(os.path.join(tmp, leftover))
            if problems:
                failures.append(f"{shown}: {'; '.join(problems)}\n    stderr: {err.strip()[:400]}")
        print(f"{len(CASES)} cases over {len(programs)} programs ({', '.join(sorted(programs))})")
        for f in failures:
            print("FAIL " + f)
        print(f"{len(CASES) - len(failures)} of {len(CASES)} cases pass")
        return 1 if failures else 0
    finally:
        shutil.rmtree(tmp, ignore_errors=True)


if __name__ == "__main__":
    sys.exit(main())
