"""The Python module against the library: the same numbers as the slab program, standard
errors, threads, material files, radiance along rays, errors as ValueError, the README's
example. Small photon counts: the whole file runs in seconds."""
import json
import os
import pathlib
import re
import subprocess
import threading

import numpy as np
import pytest

import secchi

ROOT = pathlib.Path(__file__).resolve().parents[2]
MATERIALS = ROOT / "examples" / "materials"
SMALL = dict(photons=20_000, seed=3)


def test_solve_gives_arrays_with_positive_standard_errors():
    r = secchi.solve(phase="petzold", albedo=0.9, sun_zenith=30, depths=[1, 3, 6], **SMALL)
    assert r.phase == "petzold"
    assert r.photons_traced == SMALL["photons"]
    np.testing.assert_array_equal(r.depths, [1.0, 3.0, 6.0])
    for name in ("ed", "eu", "eod", "eou", "lu"):
        value, se = getattr(r, name), getattr(r, name + "_se")
        assert isinstance(value, np.ndarray) and value.shape == (3,) and se.shape == (3,)
        assert np.all(value > 0) and np.all(se > 0) and np.all(se < value), name
    # Ed falls off as exp(-Kd z), Kd between the absorption a = 0.1 and c = 1 (per m), nearly
    # the same over both depth intervals.
    kd = -np.diff(np.log(r.ed)) / np.diff(r.depths)
    assert np.all((kd > 0.1) & (kd < 1.0))
    assert abs(kd[0] - kd[1]) < 0.25 * kd.mean()
    assert np.all(r.eod > r.ed) and np.all(r.eou > r.eu) and np.all(r.eu < r.ed)


SLAB_CASES = [
    (dict(phase="petzold", albedo=0.9, sun_zenith=30), ["--phase", "petzold", "--albedo", "0.9", "--sun-zenith", "30"]),
    (dict(phase="hg:0.8", albedo=0.7, sun_zenith=50, bottom_depth=4, bottom_albedo=0.3, store="voi-grid", wind=5),
     ["--phase", "hg:0.8", "--albedo", "0.7", "--sun-zenith", "50", "--bottom-depth", "4", "--bottom-albedo", "0.3",
      "--store", "voi-grid", "--wind", "5"]),
    (dict(phase="petzold", albedo=0.2, sun_zenith=30, backscatter_bias=0.2),
     ["--phase", "petzold", "--albedo", "0.2", "--sun-zenith", "30", "--backscatter-bias", "0.2"]),
    (dict(phase="petzold", albedo=0.9, sun_zenith=30, tracer="lanes-float", store="voi-grid"),
     ["--phase", "petzold", "--albedo", "0.9", "--sun-zenith", "30", "--tracer", "lanes-float", "--store", "voi-grid"]),
    (dict(phase="hg:0.9", albedo=0.2, sun_zenith=10, tracer="lanes", backscatter_bias=0.2, bottom_depth=3,
          bottom_albedo=0.5),
     ["--phase", "hg:0.9", "--albedo", "0.2", "--sun-zenith", "10", "--tracer", "lanes", "--backscatter-bias", "0.2",
      "--bottom-depth", "3", "--bottom-albedo", "0.5"]),
]


def test_depth_importance_is_slabs_auto_unless_given():
    # w0 = 0.9, c = 1: tau_a = 1 down to 10 m, past ln 2: on by default; 0 turns it off.
    deep = dict(phase="isotropic", albedo=0.9, depths=[1, 10], **SMALL)
    assert secchi.solve(**deep).depth_importance.startswith("auto: mu_i = 1")
    assert secchi.solve(**deep, importance_cosine=0).depth_importance == "off"
    assert secchi.solve(**deep, importance_cosine=0.5).depth_importance == "given"
    assert secchi.solve(**dict(deep, depths=[1, 5])).depth_importance.startswith("auto: off")
    assert secchi.trace_map(**deep).first_pass.depth_importance.startswith("auto: mu_i = 1")


@pytest.mark.skipif("SECCHI_SLAB" not in os.environ, reason="the slab program (SECCHI_SLAB) was not built")
@pytest.mark.parametrize("keywords, options", SLAB_CASES)
def test_solve_is_bit_identical_to_slab(tmp_path, keywords, options):
    out = tmp_path / "slab.json"
    subprocess.run([os.environ["SECCHI_SLAB"], *options, "--depths", "1,2.5", "--photons", "20000", "--seed", "3",
                    "--json", str(out)], check=True, stdout=subprocess.DEVNULL)
    slab = json.loads(out.read_text())
    r = secchi.solve(depths=[1, 2.5], **keywords, **SMALL)
    assert r.phase == slab["phase"]["name"]
    assert r.depth_importance == slab["depth_importance"]["chosen"]
    assert r.photons_stored == slab["photons_stored"]
    for name, key in (("ed", "Ed"), ("eu", "Eu"), ("eod", "Eod"), ("eou", "Eou"), ("lu", "Lu")):
        np.testing.assert_array_equal(getattr(r, name), [d[key] for d in slab["depths"]], err_msg=name)
        np.testing.assert_array_equal(getattr(r, name + "_se"), [d[key + "_se"] for d in slab["depths"]])


def test_trace_map_takes_the_tracer_of_solve():
    keywords = dict(phase="petzold", depths=[1, 4], tracer="lanes", **SMALL)
    first = secchi.trace_map(**keywords).first_pass
    both = secchi.solve(**keywords, store="voi-grid")
    for name in ("ed", "ed_se", "eu", "eu_se", "eod", "eod_se", "eou", "eou_se"):
        np.testing.assert_array_equal(getattr(first, name), getattr(both, name), err_msg=name)
    photon = secchi.solve(**dict(keywords, tracer="photon"), store="voi-grid")
    assert not np.array_equal(photon.ed, both.ed)  # another tracer draws other photons


@pytest.mark.parametrize("tracer", ["photon", "lanes-float"])
def test_threads_do_not_change_the_numbers(tracer):
    one = secchi.solve(phase="rayleigh", depths=[0.5, 2], threads=1, tracer=tracer, **SMALL)
    two = secchi.solve(phase="rayleigh", depths=[0.5, 2], threads=2, tracer=tracer, **SMALL)
    for name in ("ed", "ed_se", "eu", "eu_se", "eod", "eod_se", "eou", "eou_se", "lu", "lu_se"):
        np.testing.assert_array_equal(getattr(one, name), getattr(two, name), err_msg=name)


def test_solve_releases_the_gil():
    done, ticks = threading.Event(), [0]

    def run():
        secchi.solve(phase="isotropic", photons=100_000, depths=[1])
        done.set()

    worker = threading.Thread(target=run)
    worker.start()
    while not done.is_set():
        ticks[0] += 1
    worker.join()
    assert ticks[0] > 1000  # this thread ran while the photons were traced


def test_read_material_gives_the_iops_at_depth_nodes():
    m = secchi.read_material(str(MATERIALS / "case1_chlorophyll.mat"), 490)
    assert m.wavelength_nm == 490
    assert m.depths.shape == (2001,) and m.depths[0] == 0 and m.depths[-1] == 100
    assert len(m.phases) == m.component_scattering.shape[0] == 2
    np.testing.assert_allclose(m.scattering, m.component_scattering.sum(axis=0), rtol=1e-12)
    np.testing.assert_allclose(m.attenuation, m.absorption + m.scattering, rtol=1e-12)
    assert np.all(m.absorption > 0) and np.all(m.scattering > 0)
    assert 1.33 < m.refractive_index < 1.35  # IAPWS pure water
    # The chlorophyll profile is Gaussian in depth: the IOPs vary, peaking below the surface.
    assert 0 < m.depths[np.argmax(m.absorption)] < 100
    coarse = secchi.read_material(str(MATERIALS / "case1_chlorophyll.mat"), 490, depths=[0, 10, 30])
    np.testing.assert_array_equal(coarse.depths, [0, 10, 30])
    np.testing.assert_allclose(coarse.absorption, m.absorption[[0, 200, 600]], rtol=1e-12)
    # A material's water is solved like natural_water does (solve_stratified).
    r = secchi.solve(water=m, depths=[1, 5], photons=10_000)
    assert r.phase.startswith("mixture") and np.all(r.ed > 0) and np.all(r.lu_se > 0)


def test_read_material_of_a_pure_water_file():
    m = secchi.read_material(MATERIALS / "purewater.mat", 500, depths=[0, 1])  # a str or any os.PathLike
    assert m.path == str(MATERIALS / "purewater.mat")
    np.testing.assert_allclose(m.absorption, m.absorption[0])  # homogeneous
    assert 0.01 < m.absorption[0] < 0.05 and 0.001 < m.scattering[0] < 0.005  # pure water at 500 nm


@pytest.fixture(scope="module")
def bottom_map():
    keywords = dict(phase="petzold", albedo=0.8, sun_zenith=30, bottom_depth=6, bottom_albedo=0.3, depths=[2, 4],
                    threads=2, **SMALL)
    return keywords, secchi.trace_map(**keywords)


def test_radiance_along_rays(bottom_map):
    _, m = bottom_map
    assert m.stored > 0 and m.first_pass.lu is None and m.first_pass.ed.shape == (2,)
    theta = np.radians(np.linspace(0, 170, 18))  # from nadir (looking down) to near zenith
    directions = np.stack([np.sin(theta), np.zeros_like(theta), np.cos(theta)], axis=1)
    values, se = m.radiance([0.3, 0.4, 3.0], directions)  # one origin for every ray
    assert values.shape == se.shape == (18,)
    assert np.all(np.isfinite(values)) and np.all(values > 0) and np.all(se > 0)
    assert values[-1] > 10 * values[0]  # looking up sees far more light than looking down
    # Directions of any length; a ray stopped at 1 m sees less than an unbounded one.
    again, _ = m.radiance(np.tile([0.3, 0.4, 3.0], (18, 1)), 2.5 * directions)
    np.testing.assert_allclose(again, values, rtol=1e-12)
    short, _ = m.radiance([0.3, 0.4, 3.0], [0, 0, 1], lengths=1.0)
    assert 0 < short[0] < values[0]


def test_radiance_averages_to_the_solvers_lu(bottom_map):
    keywords, m = bottom_map
    k, z = 10, 4.0  # the solver's Lu: the mean over a 10 x 10 grid of nadir rays in the 1 m section
    x = (np.arange(k) + 0.5) / k
    origins = np.array([[xi, yj, z] for xi in x for yj in x])
    values, _ = m.radiance(origins, [0, 0, 1])
    r = secchi.solve(**keywords, store="voi-grid")
    assert values.mean() == pytest.approx(r.lu[1], rel=1e-9)


@pytest.mark.parametrize("keywords, parameter", [
    (dict(albedo=1.5), "albedo"),
    (dict(photons=0), "photons"),
    (dict(phase="hg:1.5"), "g"),
    (dict(phase="nonsense"), "phase"),
    (dict(store="octree"), "store"),
    (dict(absorption="none"), "absorption"),
    (dict(bottom_albedo=0.5), "bottom_albedo"),
    (dict(bottom_depth=-1.0), "bottom depth"),
    (dict(sun_zenith=95), "zenith"),
    (dict(radius=0.8), "radius"),
    (dict(backscatter_bias=1.0), "backscatter bias"),
    (dict(backscatter_bias=0.2, phase="isotropic"), "phase"),
    (dict(backscatter_bias=0.2, absorption="analog"), "backscatter bias"),
    (dict(tracer="gpu"), "tracer"),
])
def test_invalid_input_raises_value_error_naming_the_parameter(keywords, parameter):
    with pytest.raises(ValueError, match=re.escape(parameter)) as e:
        secchi.solve(**{"photons": 1000, **keywords})
    assert isinstance(e.value, secchi.InputError) and str(e.value).startswith("invalid ")


def test_invalid_material_and_rays_raise_value_error(tmp_path, bottom_map):
    with pytest.raises(ValueError, match="missing.mat"):
        secchi.read_material(str(tmp_path / "missing.mat"), 500)
    bad = tmp_path / "bad.mat"
    bad.write_text("BULK_PROPERTIES {\n  IOP_MODEL {\n    BASE_MEDIUM = seawater\n  }\n}\n")
    with pytest.raises(ValueError, match="BASE_MEDIUM"):
        secchi.read_material(str(bad), 500)
    with pytest.raises(ValueError, match="wavelength_nm"):
        secchi.read_material(str(MATERIALS / "purewater.mat"), -1)
    m = secchi.read_material(str(MATERIALS / "purewater.mat"), 500, depths=[0, 1])
    with pytest.raises(ValueError, match="phase"):
        secchi.solve(water=m, phase="petzold", photons=1000)
    _, photon_map = bottom_map
    with pytest.raises(ValueError, match="origins"):
        photon_map.radiance(np.zeros((4, 2)), [0, 0, 1])
    with pytest.raises(ValueError, match="directions"):
        photon_map.radiance([0, 0, 1], [0, 0, 0])
    with pytest.raises(ValueError, match="rays"):
        photon_map.radiance(np.zeros((4, 3)), np.ones((3, 3)))
    with pytest.raises(ValueError, match="band"):
        photon_map.radiance([0, 0, 1], [0, 0, 1], band=1)


def test_the_readmes_example_runs(capsys, monkeypatch):
    monkeypatch.chdir(ROOT)  # its paths are the repository's
    readme = (ROOT / "README.md").read_text()
    blocks = re.findall(r"```python\n(.*?)```", readme, re.S)
    assert len(blocks) == 1 and len(blocks[0].splitlines()) <= 10
    exec(compile(blocks[0], "README.md", "exec"), {})
    out = capsys.readouterr().out
    assert "Ed" in out and "L" in out and "nan" not in out
