"""Config validation: each kind of bad config fails with the key named, before any job runs."""

import copy
from pathlib import Path

import numpy as np
import pytest
import yaml

from clutchlab import config, studies
from clutchlab.config import ConfigError

ROOT = Path(__file__).resolve().parents[1]


@pytest.fixture
def raw():
    return yaml.safe_load((ROOT / "config" / "config.yaml").read_text())


@pytest.mark.parametrize("name", sorted(p.name for p in (ROOT / "config").glob("*.yaml")))
def test_shipped_configs_resolve(name, tmp_path, monkeypatch):
    from conftest import refine_sources, write_first_stage

    for source in refine_sources(
        config.read_file(ROOT / "config" / name)
    ):  # a second stage reads a first
        monkeypatch.chdir(tmp_path)
        write_first_stage(tmp_path / source)
    cfg = config.load(ROOT / "config" / name)
    for study in cfg["studies"]:
        sec = cfg[study]
        assert all(isinstance(v, float) for v in sec["fixed"].values())
        if "youngs_modulus" in sec["fixed"]:
            assert sec["fixed"]["youngs_modulus"] == pytest.approx(206e9)


def test_units_converted_and_defaults_filled(raw):
    raw["diaphragm_spring"]["parameters"] = {"sheet_thickness": "2.5 mm"}
    sec = config.resolve(raw)["diaphragm_spring"]
    assert sec["fixed"]["sheet_thickness"] == pytest.approx(2.5e-3)
    assert sec["fixed"]["friction_coefficient"] == pytest.approx(
        0.4
    )  # default from the study table
    assert sec["chunks"] == config.DEFAULT_CHUNKS and sec["factors"] == {}


def test_factor_forms(raw):
    p = raw["diaphragm_spring"]["parameters"]
    p["sheet_thickness"] = {"min": "1 mm", "max": "4 mm", "num": 3, "scale": "log"}
    sec = config.resolve(raw)["diaphragm_spring"]
    assert sec["factors"]["sheet_thickness"]["values"] == pytest.approx([1e-3, 2e-3, 4e-3])


def _expect(raw, key, *fragments):
    with pytest.raises(ConfigError) as exc:
        config.resolve(raw)
    assert exc.value.key == key, str(exc.value)
    assert f"'{key}'" in str(exc.value)
    for f in fragments:
        assert f in str(exc.value)


def test_unknown_top_level_key(raw):
    raw["chunkz"] = 3
    _expect(raw, "chunkz", "unknown key")


def test_unknown_parameter(raw):
    raw["diaphragm_spring"]["parameters"]["sheet_thicknes"] = "2 mm"
    _expect(raw, "diaphragm_spring.parameters.sheet_thicknes", "unknown key")


def test_wrong_type(raw):
    raw["chunks"] = "four"
    _expect(raw, "chunks", "integer")


def test_wrong_type_of_parameter(raw):
    raw["diaphragm_spring"]["parameters"]["poisson_ratio"] = [0.3]
    _expect(raw, "diaphragm_spring.parameters.poisson_ratio")


def test_missing_field(raw):
    del raw["diaphragm_spring"]["design"]
    _expect(raw, "diaphragm_spring.design", "missing")


def test_missing_studies(raw):
    del raw["studies"]
    _expect(raw, "studies", "missing")


def test_missing_section(raw):
    del raw["diaphragm_spring"]
    _expect(raw, "diaphragm_spring", "section missing")


def test_negative_thickness(raw):
    raw["diaphragm_spring"]["parameters"]["sheet_thickness"] = "-2 mm"
    _expect(raw, "diaphragm_spring.parameters.sheet_thickness", "must be > 0")


def test_negative_value_inside_factor(raw):
    raw["diaphragm_spring"]["parameters"]["sheet_thickness"] = {"values": ["2 mm", "-1 mm"]}
    _expect(raw, "diaphragm_spring.parameters.sheet_thickness.values[1]", "must be > 0")


def test_wrong_dimension(raw):
    raw["diaphragm_spring"]["parameters"]["outer_radius"] = "110 kg"
    _expect(raw, "diaphragm_spring.parameters.outer_radius", "expected something convertible")


def test_poisson_above_half(raw):
    raw["diaphragm_spring"]["parameters"]["poisson_ratio"] = 0.5
    _expect(raw, "diaphragm_spring.parameters.poisson_ratio", "< 0.5")


def test_min_not_below_max(raw):
    raw["diaphragm_spring"]["parameters"]["sheet_thickness"] = {
        "min": "3 mm",
        "max": "2 mm",
        "num": 3,
    }
    _expect(raw, "diaphragm_spring.parameters.sheet_thickness", "below max")


def test_factorial_needs_num(raw):
    raw["diaphragm_spring"]["parameters"]["sheet_thickness"] = {"min": "1 mm", "max": "2 mm"}
    _expect(raw, "diaphragm_spring.parameters.sheet_thickness.num", "required")


def test_sampled_design_needs_samples(raw):
    raw["diaphragm_spring"]["design"] = "lhs"
    _expect(raw, "diaphragm_spring.samples", "required")


def test_sampled_design_takes_a_values_list_as_a_discrete_factor(raw):
    raw["diaphragm_spring"]["design"] = "sobol"
    raw["diaphragm_spring"]["samples"] = 64
    raw["diaphragm_spring"]["parameters"] = {"radius_ratio": {"values": [1.2, 1.3]}}
    assert config.resolve(raw)["diaphragm_spring"]["factors"]["radius_ratio"] == {
        "values": [1.2, 1.3]
    }
    raw["diaphragm_spring"]["parameters"] = {"radius_ratio": {"values": [1.2, 1.2]}}
    _expect(raw, "diaphragm_spring.parameters.radius_ratio.values", "distinct")


def test_bad_option(raw):
    raw["diaphragm_spring"]["options"]["friction_radius"] = "parabolic"
    _expect(raw, "diaphragm_spring.options.friction_radius")


def test_option_choices_per_scenario_only_in_sampled_designs(raw):
    """Issue 16 item 3: an option given as {values: [...]} is drawn per scenario by a sampled
    design; a factorial design, an unknown or a repeated choice is refused, naming the key."""
    sec = raw["roller"]
    sec["options"]["mode"] = {"values": ["bidirectional_lock", "overrun_forward"]}
    _expect(raw, "roller.options.mode")  # the default config's roller study is a factorial grid
    sec["options"]["stress_reading"] = {"values": ["all", "one_flank"]}
    sec.update(design="sobol", samples=8, seed=1)
    _expect(raw, "roller.options.stress_reading", "chooses a model")  # never ranked together
    sec["options"]["stress_reading"] = "one_flank"
    sec["parameters"] = {"wedge_angle": {"min": "7 deg", "max": "15 deg"}}
    r = config.resolve(raw)["roller"]
    assert r["option_factors"] == {"mode": ["bidirectional_lock", "overrun_forward"]}
    assert r["options"]["mode"] == "bidirectional_lock"
    sec["parameters"]["rollers"] = {"values": [6, 7]}
    _expect(raw, "roller.parameters.rollers", "even")  # a one-flank reading meets 7 rollers
    sec["options"]["stress_reading"] = "all"
    assert config.resolve(raw)["roller"]["factors"]["rollers"] == {"values": [6.0, 7.0]}
    sec["options"]["mode"] = {"values": ["bidirectional_lock", "sideways"]}
    _expect(raw, "roller.options.mode.values.1", "sideways")
    sec["options"]["mode"] = {"values": ["overrun_forward", "overrun_forward"]}
    _expect(raw, "roller.options.mode.values")
    sec["options"]["mode"] = {"values": ["overrun_forward"], "weights": [1]}
    _expect(raw, "roller.options.mode.weights", "unknown key")


def test_schema_lists_exactly_the_study_parameters():
    schema = config.schema()
    for name in schema["properties"]["studies"]["items"]["enum"]:
        props = schema["properties"][name]["allOf"][1]["properties"]["parameters"]["properties"]
        assert set(props) == {p.name for p in studies.get(name).parameters}


def test_resolve_does_not_mutate_input(raw):
    before = copy.deepcopy(raw)
    config.resolve(raw)
    assert raw == before


def test_seed000_config_reproduces_the_paper():
    """config/seed000.yaml: lock-up 0.150 s (tol 1 %), about 5800 J (tol 2 %) at the 0.15 s ramp,
    and the shortened/lengthened variants lock up at 0.1 s and 0.2 s (seed 000 section 5.2)."""
    from clutchlab import pipeline
    from clutchlab.published import DIAPHRAGM_CLUTCH as PUB

    ds = pipeline.run_study(config.load(ROOT / "config" / "seed000.yaml")["engagement"])
    published = PUB["lockup_time"].value
    assert ds["lockup_time"].values == pytest.approx([0.1, published, 0.2], rel=0.01)
    work = float(ds["slip_work"].sel(ramp_time=0.15))
    assert work == pytest.approx(PUB["slip_work"].value, rel=0.02)


MALFORMED = sorted((Path(__file__).parent / "malformed").glob("*.yaml"))


def _expected_key(path):
    return path.read_bytes().split(b"\n", 1)[0].decode().removeprefix("# expect:").strip()


def test_there_are_malformed_configs_of_every_class():
    assert len(MALFORMED) >= 40


@pytest.mark.parametrize("path", MALFORMED, ids=lambda p: p.stem)
def test_malformed_config_is_refused_naming_the_key(path):
    """Each file of tests/malformed/ holds one mistake a user made (its '# why:' line) and the key
    (or, for a file that is not a config at all, the file) the refusal must name."""
    with pytest.raises(ConfigError) as exc:
        config.load(path)
    key = Path(exc.value.key).name if exc.value.key.endswith(".yaml") else exc.value.key
    assert key == _expected_key(path), str(exc.value)
    assert "\n" not in str(exc.value)


def test_a_quantity_is_one_number_and_a_unit():
    from clutchlab.units import UnitError, to_si

    assert to_si("2.3 mm", "m") == pytest.approx(2.3e-3)
    assert to_si("2.1e3 N s/mm", "N s/m") == pytest.approx(2.1e6)
    assert to_si("1e-2 kg m^2", "kg m^2") == pytest.approx(1e-2)
    assert to_si(" 38.84° ", "rad") == pytest.approx(np.deg2rad(38.84))
    assert to_si("3.7", "N") == 3.7  # a bare number in a string is SI, like a bare number
    for bad in ("2,3 mm", "2 3 mm", "1/2 mm", "2.3 mm mm", "mm", "inf m", "two mm"):
        with pytest.raises(UnitError):
            to_si(bad, "m")


def test_the_ceiling_can_be_raised_on_purpose(raw):
    raw["diaphragm_spring"]["parameters"]["sheet_thickness"] = {
        "min": "2 mm",
        "max": "3 mm",
        "num": 100,
    }
    n = int(
        np.prod(
            [len(f["values"]) for f in config.resolve(raw)["diaphragm_spring"]["factors"].values()]
        )
    )
    raw["max_scenarios"] = n - 1
    _expect(raw, "diaphragm_spring", f"the design has {n} scenarios", f"max_scenarios: {n}")
    raw["max_scenarios"] = n
    assert config.resolve(raw)["max_scenarios"] == n


def test_even_roller_counts_and_any_count_for_the_all_reading():
    raw = {
        "studies": ["roller"],
        "roller": {
            "design": "factorial",
            "parameters": {"rollers": {"values": [9, 13]}},
            "options": {"stress_reading": "all"},
        },
    }
    assert config.resolve(raw)["roller"]["factors"]["rollers"]["values"] == [9.0, 13.0]


@pytest.mark.parametrize("profile", ["default", "slurm"])
def test_workflow_profiles_check_config_files_first(profile, monkeypatch, tmp_path):
    """Both shipped workflow profiles run clutchlab.config.precheck_argv while Snakemake reads them
    (before it loads --configfile): a good file passes, a template is refused in one line."""
    import yte

    text = (ROOT / "workflows" / "profiles" / profile / "config.yaml").read_text()
    monkeypatch.setattr(
        "sys.argv", ["snakemake", "--configfile", str(ROOT / "config" / "small.yaml")]
    )
    assert yte.process_yaml(text, require_use_yte=True)["rerun-incomplete"] is True
    monkeypatch.setattr(
        "sys.argv", ["snakemake", "--configfile", str(ROOT / "tests/malformed/use_yte.yaml")]
    )
    with pytest.raises(SystemExit, match="^clutchlab: config key '__use_yte__'"):
        yte.process_yaml(text, require_use_yte=True)


def test_precheck_reads_every_configfile_form(tmp_path):
    good, bad = str(ROOT / "config" / "small.yaml"), str(ROOT / "tests/malformed/not_utf8.yaml")
    config.precheck_argv(["--cores", "2", "--configfile", good, "--config", "chunks=2"])
    for argv in (
        ["--configfile", good, bad],
        ["--configfiles", bad],
        [f"--configfile={bad}"],
        ["-n", "--configfile", good, "--configfile", bad],
    ):
        with pytest.raises(SystemExit, match="not UTF-8"):
            config.precheck_argv(argv)


def test_chunk_jobs_from_a_target_chunk_size(raw):
    """Issue 16 item 1: chunk_size (scenarios per job) gives ceil(N / chunk_size) jobs, at most 32 a
    study; a study's own chunks/chunk_size wins over the top-level one; both at one level refused."""
    sobol = {
        "design": "sobol",
        "samples": 1_000_000,
        "seed": 1,
        "parameters": {"ramp_time": {"min": "0.05 s", "max": "0.3 s"}},
    }
    cfg = {"studies": ["engagement"], "chunk_size": 50_000, "engagement": dict(sobol)}
    assert config.resolve(cfg)["engagement"]["chunks"] == 20
    cfg["chunk_size"] = 1000
    assert config.resolve(cfg)["engagement"]["chunks"] == config.MAX_CHUNKS_FROM_SIZE
    cfg["engagement"]["chunks"] = 3
    assert config.resolve(cfg)["engagement"]["chunks"] == 3
    cfg["engagement"] = {**sobol, "samples": 10, "chunk_size": 4}
    assert config.resolve(cfg)["engagement"]["chunks"] == 3  # ceil(10 / 4)
    for where, key in ((cfg["engagement"], "engagement.chunk_size"), (cfg, "chunk_size")):
        where["chunks"] = 2
        where["chunk_size"] = 5
        with pytest.raises(ConfigError, match=f"'{key}'"):
            config.resolve(cfg)
        where.pop("chunks")
    raw.pop("chunks")
    assert config.resolve(raw)["engagement"]["chunks"] == config.DEFAULT_CHUNKS
