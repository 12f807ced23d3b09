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
    _expect(raw, "diaphragm_spring.parameters.outer_radius", "is a mass; this value is a length")


@pytest.mark.parametrize(
    "key, given, fragment",
    [
        ("engine_speed", "5 m", "is a length; this value is a rotational speed (in rad/s"),
        ("damper_stiffness", "5 N*m*s/rad", "this value is a torsional stiffness"),
        ("ramp_time", "5 s s", "of no kind this config uses (its dimensions: [time] ** 2); this"),
        ("ramp_time", "5 foo", "'foo' is not a unit"),
        ("engine_speed", "2000 U/min", "U is read as the enzyme unit, not a revolution (U/min)"),
        ("load_torque", "80 kg*m^2/s^2", "not written as a torque: give a force times a length"),
        ("load_torque", "80 kg*m^2/s^2", "(J, kWh, kg*m^2/s^2) is taken for work and energy"),
    ],
)
def test_a_unit_of_the_wrong_kind_is_named_in_words(key, given, fragment):
    _expect(_study("engagement", {key: given}), f"engagement.parameters.{key}", fragment)


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
    assert len(MALFORMED) >= 160
    stems = {p.stem for p in MALFORMED}
    for prefix, members in (
        ("speed_", 6),
        ("yaml11_", 15),
        ("torque_in_", 4),
        ("results_", 4),
        ("constraint_", 6),
    ):
        assert sum(s.startswith(prefix) for s in stems) >= members, prefix


@pytest.mark.parametrize("path", MALFORMED, ids=lambda p: p.stem)
def test_malformed_config_is_refused_naming_the_key(path, monkeypatch):
    """Each file of tests/malformed/ holds one mistake a user made (its '# why:' line) and the key
    (or, for a file that is not a config at all, the file) the refusal must name. Read from the
    workflow's folder, as Snakemake reads it (a results folder is checked relative to it)."""
    monkeypatch.chdir(ROOT)
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
    # (num 1200: the spring grid, 198 000 scenarios, is then larger than every other study of the
    # default config: the robust sprag study has 194 400)
    raw["diaphragm_spring"]["parameters"]["sheet_thickness"] = {
        "min": "2 mm",
        "max": "3 mm",
        "num": 1200,
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


# --- reading as meant, or refusing: speeds, temperatures, kinds, magnitudes, relations ----------


def _study(name, parameters=None, **section):
    return {
        "studies": [name],
        name: {"design": "factorial", **section, "parameters": parameters or {}},
    }


def test_every_default_is_plausible_and_every_temperature_has_a_kind():
    """The seed design passes its own checks; a temperature parameter or output says whether it
    is on the scale or a difference."""
    for name in config.schema()["properties"]["studies"]["items"]["enum"]:
        study = studies.get(name)
        for p in study.parameters:
            assert p.check(p.default) is None, (name, p.name)
            assert (p.units == "K") == (p.kind in ("absolute", "difference")), (name, p.name)
        for out in study.outputs:
            units, kind = study.output_units(out)
            assert (units == "K") == (kind in ("absolute", "difference")), (name, out)
    eng = studies.get("engagement")
    assert eng.output_units("bulk_temperature_rise") == ("K", "difference")
    assert eng.output_units("peak_surface_temperature") == ("K", "absolute")


@pytest.mark.parametrize(
    "name, key, given, expected",
    [
        ("centrifugal", "rated_speed", "91.67 Hz", 91.67 * 2 * np.pi),  # 5500 rpm, not 875
        ("centrifugal", "idle_speed", "2100 1/min", 2100 * np.pi / 30),
        ("engagement", "engine_speed", "6000 1/min", 200 * np.pi),
        ("engagement", "stribeck_speed", "2 Hz", 4 * np.pi),
        ("roller", "rated_speed", "2000 rpm", 2000 * np.pi / 30),
        ("sprag", "initial_speed", "10 rev/s", 20 * np.pi),
        ("engagement", "ambient_temperature", "40 degC", 313.15),
        ("engagement", "temperature_limit", "482 degF", 523.15),
        ("diaphragm_spring", "friction_coefficient", "40 %", 0.4),
        ("centrifugal", "pressure_angle", "38.84 deg", np.deg2rad(38.84)),
        ("diaphragm_spring", "max_engine_torque", "0.173 kN*m", 173.0),
    ],
)
def test_values_are_read_as_meant(name, key, given, expected):
    assert config.resolve(_study(name, {key: given}))[name]["fixed"][key] == pytest.approx(
        expected, rel=1e-12
    )


def test_the_friction_tables_slip_speeds_in_hz_are_revolutions():
    sec = config.resolve(
        _study(
            "engagement",
            friction_table={"slip_speed": ["0 Hz", "10 Hz"], "friction_coefficient": [0.4, 0.35]},
        )
    )["engagement"]
    assert sec["options"]["friction_table"]["slip_speed"] == pytest.approx([0.0, 20 * np.pi])


@pytest.mark.parametrize(
    "output, given, expected",
    [
        ("bulk_temperature_rise", "1 degC", 1.0),  # a rise: never 274.15 K
        ("bulk_temperature_rise", "9 degF", 5.0),
        ("bulk_temperature_rise", "5 delta_degC", 5.0),
        ("bulk_temperature_rise", 5, 5.0),
        ("peak_surface_temperature", "200 degC", 473.15),
        ("peak_surface_temperature", "473.15 K", 473.15),
        ("slip_work", "5.8 kN*m", 5800.0),
        ("slip_work", "5.8 kJ", 5800.0),
    ],
)
def test_constraints_follow_their_outputs_kind(output, given, expected):
    sec = config.resolve(_study("engagement", constraints={output: {"max": given}}))["engagement"]
    assert sec["constraints"][output] == ["max", pytest.approx(expected, rel=1e-12)]


@pytest.mark.parametrize(
    "output, given, fragment",
    [
        ("peak_surface_temperature", 200, "needs a unit"),
        ("peak_surface_temperature", "200 delta_degC", "difference"),
        ("peak_friction_torque", "1 kJ", "torque"),
        ("accel_jump", "100 1/s^2", "angle"),
        ("bulk_temperature_rise", "6000 degF", "plausible"),
        ("lockup_time", "-1 s", "sign slip (no scenario can meet it)"),
        ("peak_jerk", "-10 rad/s^3", "never negative"),
        ("peak_friction_torque", "-1 N*m", "never negative"),
        ("slip_work", "-5 kJ", "never negative"),
        ("bulk_temperature_rise", "-5 delta_degC", "never negative"),
    ],
)
def test_constraints_of_the_wrong_kind_are_refused(output, given, fragment):
    cfg = _study("engagement", constraints={output: {"max": given}})
    _expect(cfg, f"engagement.constraints.{output}.max", fragment)


def test_outputs_of_the_never_negative_units_are_not_negative():
    """The rule above holds for every study's outputs of those units: every scenario of the small
    config (and the engagement's source design) gives none below 0."""
    from clutchlab import doe, pipeline

    cfg = config.load(ROOT / "config" / "small.yaml")
    for name in studies.REGISTRY:
        s = studies.get(name)
        if name in cfg:
            ds = pipeline.run_chunk(doe.build_design(cfg[name]), cfg[name]["options"], 1, 0)
        else:
            ds = s.compute(dict(s.defaults), s.full_options())
        for out in s.outputs:
            units, kind = s.output_units(out)
            if units in config.NEVER_NEGATIVE_UNITS or kind is not None:
                v = ds[out].values
                assert not np.any(v[np.isfinite(v)] < 0), (name, out)


@pytest.mark.parametrize(
    "name, output, given, fragment",
    [
        ("roller", "engagement_time", 0.5, "meant in ms"),  # 0.5 s past a 3 ms window
        ("engagement", "lockup_time", 500, "meant in ms"),
        ("engagement", "lockup_time", "0.7 s", "lengthen end_time"),  # past the 0.5 s window
    ],
)
def test_a_time_limit_past_the_simulated_window_is_refused(name, output, given, fragment):
    """The time is found only within [0, end_time]: a maximum past its end never binds (one at
    its end says "within the window", as the study's default of 0.5 s does)."""
    cfg = _study(name, constraints={output: {"max": given}})
    _expect(cfg, f"{name}.constraints.{output}.max", "never binds", fragment)


@pytest.mark.parametrize(
    "name, output, given, hint",
    [
        ("engagement", "wear_per_engagement", 0.5, "'0.5 mm'"),
        ("roller", "backlash_angle", 3, "'3 deg'"),
    ],
)
def test_a_bare_limit_meant_in_another_unit_is_refused(name, output, given, hint):
    cfg = _study(name, constraints={output: {"max": given}})
    _expect(cfg, f"{name}.constraints.{output}.max", "plausible range", hint)


def test_a_time_limit_within_the_window_is_read():
    sec = config.resolve(_study("roller", constraints={"engagement_time": {"max": "0.5 ms"}}))
    assert sec["roller"]["constraints"]["engagement_time"] == ["max", pytest.approx(5e-4)]
    sec = config.resolve(_study("engagement", constraints={"lockup_time": {"max": "0.5 s"}}))
    assert sec["engagement"]["constraints"]["lockup_time"] == ["max", 0.5]  # end_time's default


def test_a_negative_limit_is_refused_only_on_an_output_that_is_never_negative():
    """A margin's or a valley load's limit may be negative; a minimum lock-up time may not."""
    _expect(
        _study("engagement", constraints={"lockup_time": {"min": "-0.1 s"}}),
        "engagement.constraints.lockup_time.min",
        "every scenario meets it",
    )
    for name, output in (
        ("sprag", "margin_contact_inner"),
        ("diaphragm_spring", "load_valley"),
        ("engagement", "accel_jump"),
    ):
        sec = config.resolve(_study(name, constraints={output: {"min": -0.5}}))[name]
        assert sec["constraints"][output] == ["min", -0.5]


@pytest.mark.parametrize(
    "name, key, given, fragments",
    [
        ("diaphragm_spring", "sheet_thickness", "2.3 Mm", ["2.3 Mm", "0.0001 to 0.02 m"]),
        ("sprag", "sprags", 1_000_000, ["1e+06", "count"]),
        ("centrifugal", "shoes", 1e20, ["1e+20", "count"]),
        ("sprag", "youngs_modulus", 1e308, ["1e+308 Pa", "1.2e+12 Pa"]),
        ("engagement", "engine_speed", 1e300, ["1e+300 rad/s"]),
        ("engagement", "engine_speed", "16 kHz", ["16 kHz = 100531 rad/s"]),
        ("roller", "friction_coefficient", 12, ["<= 2"]),
        ("engagement", "damper_stiffness", "1e15 N*m/rad", ["1e+15 N m/rad"]),
        ("engagement", "ramp_time", "2 d", ["172800 s", "300 s"]),
        # a length, a modulus, a time, a mass, an angle written without the unit they were meant in
        ("engagement", "cushion_travel", 0.6, ["0.6 m", "write the unit, e.g. '0.6 mm'"]),
        # a number as text (Snakemake's --config gives one so) is a bare number too
        ("engagement", "cushion_travel", "0.6", ["0.6 m", "write the unit, e.g. '0.6 mm'"]),
        # written with its unit: the key that admits it on purpose is named
        ("engagement", "cushion_travel", "0.6 m", ["0.6 m", "set the study's key plausible"]),
        ("sprag", "youngs_modulus", 206000, ["206000 Pa", "'206000 MPa'"]),
        ("engagement", "ramp_time", 500, ["500 s", "'500 ms'"]),
        ("engagement", "youngs_modulus", 206, ["206 Pa", "'206 GPa'"]),
        ("centrifugal", "shoe_mass", 178, ["178 kg", "'178 g'"]),
        ("roller", "wedge_angle", 1, ["1 rad", "'1 deg'"]),
        ("roller", "wedge_angle", 11, ["a bare number is in rad"]),
        ("engagement", "ambient_temperature", "5000 K", ["3000 K"]),
        # an absolute temperature's range in kelvin and degrees Celsius, no "in magnitude"
        (
            "engagement",
            "ambient_temperature",
            "5000 degC",
            ["(1 to 3000 K: -272.15 to 2726.85 °C)"],
        ),
        ("engagement", "driven_inertia", "inf", ["finite"]),
        ("engagement", "driven_inertia", "1e9 kg*m^2", ["(1e-09 to 100000 kg m^2)"]),
    ],
)
def test_implausible_magnitudes_are_refused_naming_the_value_as_given(name, key, given, fragments):
    _expect(_study(name, {key: given}), f"{name}.parameters.{key}", *fragments)


def test_the_unit_a_bare_number_was_meant_in_is_named_only_where_it_reads_plausibly():
    """A bare 50 for a sheet thickness is 50 m and would be 50 mm: also refused, so no hint; a
    bare 1e-12 is no slip of a unit at all."""
    for given in (50, 1e-12):
        with pytest.raises(ConfigError) as exc:
            config.resolve(_study("engagement", {"sheet_thickness": given}))
        assert "plausible range" in str(exc.value)
        assert "bare number" not in str(exc.value)


def test_a_section_of_a_study_not_run_is_checked_all_the_same():
    """`--config studies=[sprag]` with a config whose engagement section has a slip: refused now,
    not on the day the engagement study is listed; a valid section not run is fine."""
    raw = {
        "studies": ["sprag"],
        "sprag": {"design": "factorial"},
        "engagement": {"design": "factorial", "parameters": {"cushion_travel": 0.6}},
    }
    _expect(raw, "engagement.parameters.cushion_travel", "'0.6 mm'")
    raw["engagement"]["parameters"]["cushion_travel"] = "0.6 mm"
    assert sorted(config.resolve(raw)) == ["max_scenarios", "report", "results", "sprag", "studies"]


@pytest.mark.parametrize(
    "section, key",
    [
        ({"parameters": {"ramp_time": "0.1 s"}}, "engagement.parameters"),
        ({"samples": 1.5}, "engagement.samples"),
        ({}, "engagement.samples"),
        ({"samples": 8, "chunks": 2, "chunk_size": 4}, "engagement.chunk_size"),
    ],
)
def test_a_refinement_not_run_has_its_own_keys_checked(section, key):
    """A refinement's section of a study not listed: its keys are checked now (the result it
    refines is not read: it need not exist yet)."""
    refine = {"design": "refine", "refine": {"from": "no/such/file.h5"}}
    raw = {"studies": ["sprag"], "sprag": {"design": "factorial"}, "engagement": refine}
    raw["engagement"].update(section)
    _expect(raw, key)
    if key == "engagement.samples" and not section:
        raw["engagement"]["samples"] = 8
        assert "engagement" not in config.resolve(raw)


def test_zero_is_judged_by_the_parameters_own_minimum():
    sec = config.resolve(_study("engagement", {"air_gap": "0 mm", "stack_mass": 0}))["engagement"]
    assert sec["fixed"]["air_gap"] == sec["fixed"]["stack_mass"] == 0.0
    _expect(
        _study("engagement", {"cushion_travel": "0 mm"}),
        "engagement.parameters.cushion_travel",
        "> 0",
    )


def _relation_cases():
    """(study, parameters that break one relation for some scenario, the keys named)."""
    return [
        (
            "diaphragm_spring",
            {"sheet_thickness": "19 mm", "radius_ratio": 1.2},
            "sheet_thickness",
            "outer_radius",
        ),
        (
            "engagement",
            {"lining_inner_radius": "120 mm"},
            "lining_inner_radius",
            "lining_outer_radius",
        ),
        (
            "diaphragm_spring",
            {"lining_outer_radius": {"values": ["80 mm", "70 mm"]}},
            "lining_inner_radius",
            "lining_outer_radius",
        ),
        (
            "centrifugal",
            {"idle_speed": {"values": ["2000 rpm", "6000 rpm"]}},
            "idle_speed",
            "rated_speed",
        ),
        ("centrifugal", {"shoe_radius": "50 mm"}, "shoe_radius", "drum_radius"),
        ("sprag", {"inner_bore_radius": "25 mm"}, "inner_bore_radius", "inner_race_radius"),
        (
            "sprag",
            {"outer_race_radius": {"values": ["30 mm", "22 mm"]}},
            "inner_race_radius",
            "outer_race_radius",
        ),
        ("sprag", {"outer_rim_radius": "30 mm"}, "outer_race_radius", "outer_rim_radius"),
        (
            "diaphragm_spring",
            {"load_radius_inner_offset": "20 mm", "load_radius_outer_offset": "8 mm"},
            "load_radius_inner_offset",
            "radius_ratio",
        ),
        (
            "engagement",
            {"end_time": "0.2 s", "ramp_time": {"values": ["0.1 s", "0.3 s"]}},
            "end_time",
            "ramp_time",
        ),
        (
            "engagement",
            {"end_time": "20 s", "fade_coefficient": {"values": [0, 0.002]}},
            "end_time",
            "fade_coefficient",
        ),
        (
            "engagement",
            {"temperature_limit": "35 degC"},
            "temperature_limit",
            "ambient_temperature",
        ),
        (
            "engagement",
            {"fade_coefficient": 0.002, "fade_onset_temperature": "30 degC"},
            "fade_onset_temperature",
            "ambient_temperature",
        ),
        ("roller", {"rollers": {"values": [12, 100]}}, "rollers", "contact_radius"),
        ("roller", {"penetration_depth": "6 mm"}, "penetration_depth", "roller_diameter"),
        (
            "roller",
            {"control_stop_time": {"values": ["1 ms", "5 ms", "inf"]}},
            "control_stop_time",
            "end_time",
        ),
    ]


@pytest.mark.parametrize("name, params, first, other", _relation_cases())
def test_a_relation_broken_for_some_scenario_is_refused_naming_both_keys(
    name, params, first, other
):
    _expect(_study(name, params), f"{name}.parameters.{first}", f"'{name}.parameters.{other}' = ")


STUDIES = ("diaphragm_spring", "engagement", "centrifugal", "sprag", "roller")


@pytest.mark.parametrize("name", STUDIES)
def test_relations_are_checked_at_the_worst_corner_of_the_design(name):
    """A config passes the relation check exactly when every scenario of its grid meets every
    relation (the relations are monotone in each parameter): random 2 x 2 x ... grids around the
    seed design, each relation's parameters varied by up to a factor 3."""
    from itertools import product

    study = studies.get(name)
    rng = np.random.default_rng(7)
    outcomes = set()
    for rel in study.relations:
        for _ in range(25):
            values = {}
            for n in rel.names:
                p = study.parameter(n)
                d = p.default if np.isfinite(p.default) and p.default else 1e-3
                values[n] = sorted({float(d * f) for f in rng.uniform(0.3, 3.0, 2)})
            grid = [dict(zip(values, combo, strict=True)) for combo in product(*values.values())]
            fails = any(not rel.holds(**g) for g in grid)
            section = {
                "name": name,
                "fixed": {},
                "factors": {n: {"values": v} for n, v in values.items()},
            }
            assert (studies.failed_relation(section, [rel]) is not None) == fails, (
                rel.text,
                values,
            )
            outcomes.add(fails)
    assert outcomes == {True, False}  # (both met and broken relations were drawn)


def test_a_zero_fade_coefficient_leaves_the_fade_relations_out():
    sec = config.resolve(
        _study("engagement", {"fade_onset_temperature": "30 degC", "end_time": "20 s"})
    )
    assert sec["engagement"]["fixed"]["fade_coefficient"] == 0.0


# --- numbers as YAML 1.2 reads them, or refused; JSON; nesting ----------------------------------

ROLLERS = (
    "studies: [roller]\nroller:\n  design: factorial\n  parameters:\n    rollers: {values: [%s]}\n"
)


@pytest.mark.parametrize(
    "text, yaml11, yaml12",
    [
        ("010", "8", "10"),  # octal in YAML 1.1
        ("012", "10", "12"),
        ("08", "'08'", "8"),
        ("0o14", "'0o14'", "12"),
        ("0b1100", "12", "'0b1100'"),
        ("-0xc", "-12", "'-0xc'"),
        ("1_2", "12", "'1_2'"),
        ("1:12", "72", "'1:12'"),  # sexagesimal
        ("1.2e1", "'1.2e1'", "12.0"),
        ("12e0", "'12e0'", "12.0"),
        ("+.5", "'+.5'", "0.5"),
        ("-.5", "'-.5'", "-0.5"),
        ("1_2.0", "12.0", "'1_2.0'"),
        ("on", "true", "'on'"),
        ("Off", "false", "'Off'"),
        ("YES", "true", "'YES'"),
        ("no", "false", "'no'"),
        ("2024-01-12", "'2024-01-12'", "'2024-01-12'"),
    ],
)
def test_a_number_yaml_11_and_12_read_differently_is_refused(tmp_path, text, yaml11, yaml12):
    f = tmp_path / "c.yaml"
    f.write_text(ROLLERS % text)
    with pytest.raises(ConfigError) as exc:
        config.read_file(f)
    assert exc.value.key == "roller.parameters.rollers.values[0]"
    assert f"{text} is read as" in str(exc.value) and f"write {yaml11}" in str(exc.value)
    assert yaml12 in str(exc.value) and "\n" not in str(exc.value)


@pytest.mark.parametrize(
    "text", ["06", "12", "+12", "12.0", "1.2e+1", "0x0c", ".inf", "1.", "true"]
)
def test_a_number_both_read_alike_is_accepted(tmp_path, text):
    f = tmp_path / "c.yaml"
    f.write_text(ROLLERS % text)
    assert config.read_file(f)["roller"]["parameters"]["rollers"]["values"][0] == yaml.safe_load(
        text
    )


def test_a_key_yaml_11_reads_as_a_boolean_is_refused(tmp_path):
    f = tmp_path / "c.yaml"
    f.write_text("studies: [sprag]\nsprag: {design: factorial}\nreport: {on: 3}\n")
    with pytest.raises(ConfigError, match="'report.on': the key on is read as the boolean true"):
        config.read_file(f)


def test_the_spellings_suggested_read_alike_in_yaml_11_and_12():
    """Every spelling a refusal suggests is read the same by YAML 1.1 (PyYAML) and 1.2."""
    import datetime

    from hypothesis import given
    from hypothesis import strategies as hs

    from clutchlab._yaml_readings import spell, yaml12

    def same(a, b):
        return type(a) is type(b) and (a == b or (a != a and b != b))

    @given(
        hs.one_of(
            hs.integers(-(10**20), 10**20),
            hs.floats(allow_nan=True, allow_infinity=True),
            hs.booleans(),
            hs.none(),
            hs.text(alphabet="0123456789abcdefxo_:.+-eE ", min_size=1, max_size=8),
        )
    )
    def check(v):
        text = spell(v)
        read11 = yaml.safe_load(f"k: {text}")["k"]
        plain = text[1:-1].replace("''", "'") if text.startswith("'") else None
        assert same(read11, v)
        assert same(yaml12(text), v) if plain is None else plain == v

    check()
    assert spell(datetime.date(2024, 1, 12)) == "'2024-01-12'"


def test_a_json_config_indented_with_tabs_is_read_as_json(tmp_path):
    import json

    f = tmp_path / "c.json"
    body = {
        "studies": ["sprag"],
        "sprag": {"design": "factorial", "parameters": {"torque": "500 N*m"}},
    }
    f.write_text(json.dumps(body, indent="\t"))
    assert config.load(f)["sprag"]["fixed"]["torque"] == 500.0
    f.write_text('{"studies": ["sprag"],\n\t"studies": ["roller"]}')
    with pytest.raises(ConfigError, match="'studies': given twice"):
        config.read_file(f)


@pytest.mark.parametrize(
    "name, text",
    [
        (
            "c.yaml",
            "studies: [engagement]\nengagement:\n  design: factorial\n  parameters:\n"
            "    ramp_time: {min: 0.1 s, max: 0.2 s, max: 0.3 s, num: 2}\n",
        ),
        (
            "c.json",
            '{"studies": ["engagement"], "engagement": {"design": "factorial", "parameters": '
            '{"ramp_time": {"min": "0.1 s", "max": "0.2 s", "max": "0.3 s", "num": 2}}}}',
        ),
    ],
)
def test_a_nested_key_given_twice_is_named_by_its_whole_path(tmp_path, name, text):
    f = tmp_path / name
    f.write_text(text)
    with pytest.raises(ConfigError) as exc:
        config.read_file(f)
    assert exc.value.key == "engagement.parameters.ramp_time.max", str(exc.value)
    assert "given twice" in str(exc.value)


@pytest.mark.parametrize("depth", [17, 500, 100_000])
@pytest.mark.parametrize("form", ["yaml", "json"])
def test_deep_nesting_is_one_line_naming_the_file_or_key(tmp_path, depth, form):
    f = tmp_path / f"c.{form}"
    nest = "[" * depth + "]" * depth
    f.write_text(
        f"studies: [sprag]\nsprag: {{design: factorial}}\nx: {nest}\n"
        if form == "yaml"
        else f'{{"studies": ["sprag"], "sprag": {{"design": "factorial"}}, "x": {nest}}}'
    )
    with pytest.raises(ConfigError) as exc:
        config.read_file(f)
    assert exc.value.key in (str(f), "x" + "[0]" * config.MAX_DEPTH)
    assert "\n" not in str(exc.value) and "nest" in str(exc.value)
    cfg = {"studies": ["sprag"], "sprag": {"design": "factorial"}}
    deep = cfg["sprag"]
    for _ in range(depth if depth < 1000 else 50):
        deep["parameters"] = {}
        deep = deep["parameters"]
    with pytest.raises(ConfigError, match="nests deeper"):
        config.resolve(cfg)


@pytest.mark.parametrize(
    "entry, expect",
    [
        ("chunks=010", 10),  # Python int(): decimal, as YAML 1.2 reads it
        ("chunks=1_0", 10),
        ("max_scenarios=1e7", 10_000_000),
        ("chunks=0x10", "chunks"),  # text: refused by the schema
        ("chunks=on", "chunks"),
        ("report={benchmark: on}", "report.benchmark"),  # nested values arrive as text
        ("report={dpi: 100}", "report.dpi"),
    ],
)
def test_snakemake_config_overrides_are_read_as_yaml_12_or_refused(raw, entry, expect):
    """`snakemake --config key=value` is parsed by Snakemake (int(), float(), True/False, else YAML
    with every scalar as text) and then resolved: a number reads as YAML 1.2 would, anything else
    where a number or a boolean belongs is refused naming the key."""
    from snakemake.cli import parse_config
    from snakemake.utils import update_config

    update_config(raw, parse_config([entry]))
    if isinstance(expect, str):
        with pytest.raises(ConfigError) as exc:
            config.resolve(raw)
        assert exc.value.key == expect
    else:
        key = entry.split("=")[0]
        assert config.resolve(raw)[key] == expect if key != "chunks" else True
        if key == "chunks":
            assert config.resolve(raw)["engagement"]["chunks"] == expect


def test_snakemake_config_override_of_a_quantity_reads_text_as_yaml_12(raw):
    from snakemake.cli import parse_config
    from snakemake.utils import update_config

    update_config(raw, parse_config(["sprag={parameters: {sprags: 010, torque: 750 N*m}}"]))
    assert config.resolve(raw)["sprag"]["fixed"]["sprags"] == 10.0  # not octal 8
    update_config(raw, parse_config(["sprag={parameters: {sprags: 0b1100}}"]))
    _expect(raw, "sprag.parameters.sprags", "0b1100")


# --- late crashes refused at config time ---------------------------------------------------------


@pytest.mark.parametrize(
    "results, fragment",
    [
        ("Snakefile", "existing file"),
        ("Snakefile/out", "is a file"),
        ("config", "config/ folder"),
        ("config/results", "config/ folder"),
        ("workflows/x", "workflows/ folder"),
        ("/proc/clutchlab_results", "cannot be written"),
    ],
)
def test_a_results_folder_that_cannot_take_results_is_refused(monkeypatch, results, fragment):
    monkeypatch.chdir(ROOT)
    _expect({**_study("sprag"), "results": results}, "results", fragment)


def test_a_results_folder_that_can_take_results_is_accepted(monkeypatch, tmp_path):
    monkeypatch.chdir(tmp_path)
    assert config.resolve({**_study("sprag"), "results": "a/b/c"})["results"] == "a/b/c"
    assert not (tmp_path / "a").exists()  # nothing made at config time


def test_curves_is_a_whole_number_up_to_the_design_size():
    sec = {"design": "sobol", "samples": 8, "parameters": {"torque": {"min": 100, "max": 200}}}
    cfg = {"studies": ["sprag"], "sprag": sec}
    for bad in (1e20, 9, 2.5):
        sec["curves"] = bad
        _expect(cfg, "sprag.curves")
    sec["curves"] = 8
    assert config.resolve(cfg)["sprag"]["curve_stride"] == 8


@pytest.mark.parametrize("design", ["lhs", "sobol", "saltelli"])
def test_a_sampled_design_without_a_factor_is_refused(design):
    _expect(_study("sprag", design=design, samples=8), "sprag.parameters", "factor")
    ok = _study(
        "engagement", design=design, samples=8, options={"profile": {"values": ["ramp", "cubic"]}}
    )
    if design != "saltelli":  # (an option drawn per scenario is a factor of a sampled design)
        assert config.resolve(ok)["engagement"]["option_factors"] == {"profile": ["ramp", "cubic"]}


# --- any text: read, or refused in one line naming the file or key ------------------------------

YAMLISH = [
    "studies: [sprag]\n",
    "sprag:\n",
    "  design: factorial\n",
    "a: ",
    "b:",
    " ",
    "\n",
    "\t",
    "[",
    "]",
    "{",
    "}",
    ",",
    ":",
    "- ",
    "&x ",
    "*x",
    "!!binary aGk=",
    "!!set {a, b}",
    "!!int ",
    "!!float ",
    "!!str ",
    "? ",
    "010",
    "on",
    "1e3",
    "2024-01-01",
    '"',
    "'",
    "#",
    "<<: *x",
    "~",
    ".inf",
    "---\n",
    "%YAML 1.2\n",
    "1:30",
    "\x00",
    "\ufeff",
    "|\n",
    '{"a": 1}',
    "[[[[",
]


def test_any_text_is_read_or_refused_in_one_line(tmp_path):
    """Config files made of YAML and JSON pieces (tags, anchors, tabs, NUL, BOM, directives):
    read_file returns a mapping or raises one ConfigError line, never another exception
    (PyYAML's constructor raised ValueError/IndexError for `!!int ` and a reader error for NUL)."""
    from hypothesis import HealthCheck, example, given, settings
    from hypothesis import strategies as hs

    f = tmp_path / "c.yaml"

    @settings(max_examples=300, deadline=None, suppress_health_check=list(HealthCheck))
    @given(hs.lists(hs.sampled_from(YAMLISH), max_size=20))
    @example(["!!int "])
    @example(["!!float ", "studies: [sprag]\n"])
    @example(["\x00"])
    def check(parts):
        f.write_text("".join(parts), encoding="utf-8")
        try:
            assert isinstance(config.read_file(f), dict)
        except ConfigError as exc:
            assert "\n" not in str(exc)

    check()


def test_any_quantity_text_converts_or_is_refused():
    """A number followed by any string of unit pieces: a finite SI value or a UnitError (pint raised
    OverflowError for m^1e308 while finding its root units)."""
    from hypothesis import HealthCheck, example, given, settings
    from hypothesis import strategies as hs

    from clutchlab.units import UnitError, to_si

    pieces = ["m", "mm", "Hz", "rpm", "deg", "degC", "delta_degC", "K", "J", "N", "*", "/", "^"]
    pieces += ["**", "2", "-1", "(", ")", " ", "%", "rad", "s", "min", "kg", "1e308", "°", "²"]
    units = ["m", "N m", "rad/s", "1", "K", "kg m^2", "N m/rad", "rad", "J", "1/K"]

    @settings(max_examples=500, deadline=None, suppress_health_check=list(HealthCheck))
    @given(hs.floats(allow_nan=False, width=64), hs.lists(hs.sampled_from(pieces), max_size=6))
    @example(0.0, ["°", "^", "1e308"])
    @example(1.0, ["2", "²", "²", "²", "²", "²"])  # 2^(2^65536): a worker filled 21 GB
    def check(number, parts):
        for unit in units:
            try:
                assert np.isfinite(
                    to_si(f"{number!r} {''.join(parts)}", unit, "absolute" if unit == "K" else None)
                )
            except UnitError:
                pass

    check()


def test_stored_temperatures_say_their_kind():
    """CF units_metadata: an absolute temperature (input or output) is on the scale, a rise and a
    per-kelvin coefficient are differences; nothing else carries it."""
    from clutchlab import doe, pipeline

    sec = config.resolve(
        _study(
            "engagement",
            {"ambient_temperature": {"values": ["30 degC", "40 degC"]}},
            options={"driveline": "rigid"},
        )
    )["engagement"]
    design = doe.build_design(sec)
    assert design["ambient_temperature"].attrs["units_metadata"] == "temperature: on_scale"
    assert design["temperature_limit"].attrs["units_metadata"] == "temperature: on_scale"
    assert design["fade_coefficient"].attrs["units_metadata"] == "temperature: difference"
    assert "units_metadata" not in design["ramp_time"].attrs
    ds = pipeline.run_study(sec)
    assert ds["bulk_temperature_rise"].attrs["units_metadata"] == "temperature: difference"
    assert ds["peak_surface_temperature"].attrs["units_metadata"] == "temperature: on_scale"
    assert ds["ambient_temperature"].attrs["units_metadata"] == "temperature: on_scale"
    assert ds["ambient_temperature"].values == pytest.approx([303.15, 313.15])
    for name, var in {**ds.coords, **ds.data_vars}.items():
        if var.attrs.get("units") == "K":
            assert var.attrs.get("units_metadata", "").startswith("temperature: "), name


@pytest.mark.parametrize(
    "sd, want",
    [("5 K", 5.0), ("5 degC", 5.0), ("5 delta_degC", 5.0), ("9 degF", 5.0), (5.0, 5.0)],
)
def test_the_sd_of_an_absolute_temperature_is_a_difference(raw, sd, want):
    """A spread is a difference whatever the parameter: 5 degC of sd is 5 K (not 278.15 K)."""
    raw["engagement"]["noise"] = {
        "ambient_temperature": {"min": "20 degC", "max": "60 degC", "dist": "normal", "sd": sd}
    }
    noise = config.resolve(raw)["engagement"]["robust"]["noise"]["ambient_temperature"]
    assert noise["sd"] == pytest.approx(want)
    assert noise["min"] == pytest.approx(293.15)


@pytest.mark.parametrize(
    "sd, fragment",
    [
        (0.05, "write the sd's unit too"),  # bare beside bounds in mm: 0.05 m?
        ("50 mm", "plausible range"),
        (0.01, "write the sd's unit too"),
        ("0.3 mm", "wider than the noise's bounds"),
    ],
)
def test_an_sd_wider_than_its_bounds_is_refused(raw, sd, fragment):
    """sd 0.3 mm on a 0.2 mm window: the normal would be a uniform; a bare sd beside bounds in
    mm is refused before it is read in metres."""
    raw["engagement"]["noise"] = {
        "cushion_travel": {"min": "0.5 mm", "max": "0.7 mm", "dist": "normal", "sd": sd}
    }
    _expect(raw, "engagement.noise.cushion_travel.sd", fragment)


def test_a_scattered_value_out_of_range_gets_no_bare_number_hint(raw):
    """The user wrote units; the value the scatter reaches is not a bare number of theirs."""
    raw["engagement"]["parameters"]["sheet_thickness"] = {"values": ["2.1 mm", "18 mm"]}
    raw["engagement"]["noise"] = {"sheet_thickness": {"scatter": "±20 %"}}
    with pytest.raises(ConfigError) as exc:
        config.resolve(raw)
    assert "plausible range" in str(exc.value) and "bare number" not in str(exc.value)


def test_the_sd_of_a_ratio_is_not_held_to_the_ratios_bounds(raw):
    """A static ratio is ≥ 1; its spread of 0.1 is not."""
    raw["engagement"]["noise"] = {
        "static_ratio": {"min": 1.0, "max": 1.5, "dist": "normal", "sd": 0.1}
    }
    noise = config.resolve(raw)["engagement"]["robust"]["noise"]["static_ratio"]
    assert noise["sd"] == pytest.approx(0.1)
    raw["engagement"]["noise"]["static_ratio"]["sd"] = 1e-30  # a slip, still refused
    _expect(raw, "engagement.noise.static_ratio.sd", "plausible")


def test_a_plausible_range_set_on_purpose_admits_an_unusual_design():
    """A shaft at 80 000 rpm (a small turbine's) is past the built-in 6 000 rad/s: refused,
    naming the key that admits it; with the study's `plausible` range it is read, and the chunk's
    per-scenario screening judges by the same range (no scenario invalid_input)."""
    from clutchlab import doe, pipeline
    from clutchlab import status as st

    section = {"rated_speed": "80000 rpm"}
    with pytest.raises(ConfigError) as exc:
        config.resolve(_study("centrifugal", section))
    assert "set the study's key plausible" in str(exc.value)
    raw = _study("centrifugal", section, plausible={"rated_speed": {"max": "100000 rpm"}})
    sec = config.resolve(raw)["centrifugal"]
    assert sec["fixed"]["rated_speed"] == pytest.approx(80000 * np.pi / 30)
    assert sec["options"]["plausible"]["rated_speed"][1] == pytest.approx(100000 * np.pi / 30)
    ds = pipeline.run_chunk(doe.build_design(sec), sec["options"], 1, 0)
    assert int(ds.status.values.reshape(-1)[0]) != st.CODE["invalid_input"]
    # the same inputs without the config's range: refused per scenario
    plain = {k: v for k, v in sec["options"].items() if k != "plausible"}
    ds = pipeline.run_chunk(doe.build_design(sec), plain, 1, 0)
    assert int(ds.status.values.reshape(-1)[0]) == st.CODE["invalid_input"]


@pytest.mark.parametrize(
    "spec, key, fragment",
    [
        ({"rated_speed": {"max": 10000}}, "rated_speed.max", "write the unit"),
        ({"rated_speed": {"max": "1e7 rpm"}}, "rated_speed.max", "any rad/s value's range"),
        ({"rated_speed": {"max": "-5 rpm"}}, "rated_speed.max", "must be within"),
        ({"rated_speed": {"max": "100 mm"}}, "rated_speed.max", "length"),
        ({"shoes": {"max": 5}}, "shoes", "a count"),
        ({"no_such": {"max": "1 m"}}, "no_such", "not a parameter of the centrifugal study"),
        ({"rated_speed": {"min": "5000 rad/s", "max": "4000 rad/s"}}, "rated_speed", "below"),
        # a narrower range refuses the value it no longer holds, saying whose range it is
        ({"rated_speed": {"min": "6000 rpm"}}, None, "with the config's plausible key"),
        # a number as text is a number without its unit; a non-finite end is no magnitude
        ({"rated_speed": {"max": "100000"}}, "rated_speed.max", "write the unit"),
        ({"rated_speed": {"max": float("nan")}}, "rated_speed.max", "finite"),
        # past the unit's range, the value read is shown; a parameter's own bound is the physics'
        ({"rated_speed": {"max": "100000 Hz"}}, "rated_speed.max", "= 628319 rad/s"),
        ({"friction_coefficient": {"max": 5}}, "friction_coefficient.max", "own bound"),
        # a range that leaves out a parameter's default (not given) is refused, not run
        ({"spring_force": {"max": "1 N"}}, "spring_force", "leaves out the parameter's default"),
    ],
)
def test_a_plausible_range_is_read_as_meant_or_refused(spec, key, fragment):
    raw = _study("centrifugal", {"rated_speed": "5000 rpm"}, plausible=spec)
    where = f"centrifugal.plausible.{key}" if key else "centrifugal.parameters.rated_speed"
    _expect(raw, where, fragment)


def test_a_plausible_minimum_does_not_hold_a_noise_sd():
    """A spread is not a value of the parameter: an sd of 100 rpm under a 1000 rpm minimum."""
    raw = _study(
        "centrifugal",
        {"rated_speed": "5500 rpm"},
        plausible={"rated_speed": {"min": "1000 rpm"}},
        noise={
            "rated_speed": {"min": "5000 rpm", "max": "6000 rpm", "dist": "normal", "sd": "100 rpm"}
        },
    )
    sd = config.resolve(raw)["centrifugal"]["robust"]["noise"]["rated_speed"]["sd"]
    assert sd == pytest.approx(100 * np.pi / 30)


def test_a_bare_number_past_its_range_is_told_to_take_its_unit_not_the_plausible_key():
    """A wider range would let the slip through (80000 meant in rpm read as 80000 rad/s)."""
    _expect(
        _study("centrifugal", {"rated_speed": 80000}),
        "centrifugal.parameters.rated_speed",
        "a bare number is in rad/s: write its unit",
    )


@pytest.mark.parametrize(
    "name, key, value",
    [("diaphragm_spring", "operating_point_factor", 5e-4), ("sprag", "compliance_factor", 1e-8)],
)
def test_the_configs_lower_end_is_the_physics(name, key, value):
    """A value the physics refuses per scenario is refused by the config, before any job."""
    _expect(_study(name, {key: value}), f"{name}.parameters.{key}", ">=")


def test_one_plausible_end_set_past_the_built_in_other_says_so():
    raw = _study("sprag", plausible={"youngs_modulus": {"max": "60 MPa"}})
    _expect(raw, "sprag.plausible.youngs_modulus", "the built-in one; give both")


def test_the_default_noise_refused_names_the_robust_key_written():
    """`robust: true` brings the study's own noise (centrifugal: μ ±20 %); a design it scatters
    past μ's bound is refused at the key the user wrote, naming the noise it brought, not at
    a noise key the user never wrote. A noise written out is named at its own key."""
    raw = _study("centrifugal", {"friction_coefficient": 1.9}, robust=True)
    _expect(
        raw,
        "centrifugal.robust",
        "the study's default noise (friction_coefficient: scatter ±20 %): the scattered value",
        "change the design's friction_coefficient or write the study's noise key",
    )
    raw["centrifugal"]["noise"] = {"friction_coefficient": {"scatter": "±20 %"}}
    _expect(raw, "centrifugal.noise.friction_coefficient", "the scattered value must be <= 2")


@pytest.mark.parametrize("name, accuracy", [("engagement", True), ("roller", False)])
def test_a_refinement_names_only_the_keys_its_study_has(name, accuracy):
    """A key a refinement takes from its first stage is refused naming what it takes: the
    engagement's accuracy, never an accuracy the roller study does not have."""
    refine = {"design": "refine", "refine": {"from": "no/such/file.h5"}, "samples": 8}
    raw = {"studies": ["sprag"], "sprag": {"design": "factorial"}, name: refine}
    raw[name]["parameters"] = {}
    with pytest.raises(ConfigError) as exc:
        config.resolve(raw)
    assert exc.value.key == f"{name}.parameters"
    assert ("options, accuracy, objectives" in str(exc.value)) == accuracy, str(exc.value)


@pytest.mark.parametrize(
    "noise, key, fragment",
    [
        # relative bounds written as factors: +90 % to +100 %, not 0.9 to 1.0 of the value
        ({"relative": [0.9, 1.0]}, "", "not factors: 0.9 to 1 is +90 % to +100 %"),
        ({"relative": ["0.9", 1.0]}, "", "not factors"),
        ({"relative": [-20, 20]}, "", "percent ('-20 %')"),
        # a bare sd beside bounds with units would be SI: 1000 times too narrow in N*m vs kN*m
        (
            {"min": "40 N*m", "max": "60 N*m", "dist": "normal", "sd": 5e-3},
            ".sd",
            "write the sd's unit too",
        ),
    ],
)
def test_a_noise_written_as_another_convention_is_refused(noise, key, fragment):
    raw = _study("engagement", robust=True)
    name = "friction_coefficient" if "relative" in noise else "load_torque"
    raw["engagement"]["noise"] = {name: noise}
    _expect(raw, f"engagement.noise.{name}{key}", fragment)


def test_a_scatter_in_percent_words_and_a_bare_sd_beside_bare_bounds_are_read():
    raw = _study("engagement", robust=True)
    raw["engagement"]["noise"] = {
        "friction_coefficient": {"scatter": "±20 percent"},
        "ambient_temperature": {"min": "20 degC", "max": "60 degC", "dist": "normal", "sd": 5},
        "specific_wear_rate": {"relative": ["+50 %", "+100 percent"]},
        "load_torque": {"min": 40, "max": 60, "dist": "normal", "sd": 5},
    }
    noise = config.resolve(raw)["engagement"]["robust"]["noise"]
    assert noise["friction_coefficient"]["max"] == pytest.approx(0.2)
    assert noise["load_torque"]["sd"] == 5.0
    assert noise["ambient_temperature"]["sd"] == 5.0  # (a bare sd of a temperature is in K)
    assert (noise["specific_wear_rate"]["min"], noise["specific_wear_rate"]["max"]) == (0.5, 1.0)


@pytest.mark.parametrize(
    "value, fragment",
    [
        (None, "has no value (null, ~ or nothing after the colon): give one, with its unit"),
        (True, "got the yes/no value true: give a number, with its unit"),
        ([0.1], "several values of a factor are written {values: [...]}"),
    ],
)
def test_a_parameter_of_the_wrong_yaml_type_is_told_what_to_write(raw, value, fragment):
    raw["engagement"]["parameters"]["ramp_time"] = value
    _expect(raw, "engagement.parameters.ramp_time", fragment)
    with pytest.raises(ConfigError) as exc:
        config.resolve(raw)
    assert "schemas" not in str(exc.value) and "None" not in str(exc.value), str(exc.value)


@pytest.mark.parametrize(
    "section, key",
    [
        ({"noise_samples": 4}, "engagement.noise_samples"),
        (
            {"parameters": {"driven_inertia": {"values": ["0.02 kg*m^2"], "role": "condition"}}},
            "engagement.parameters.driven_inertia.role",
        ),
    ],
)
def test_the_default_noise_is_named_at_the_key_that_made_the_study_robust(section, key):
    """Robust by its noise_samples or a role (no robust key): a refusal of the default noise
    names that key; so does the friction table's refusal of a scattered μ."""
    extra = {k: v for k, v in section.items() if k != "parameters"}
    raw = _study("engagement", {"friction_coefficient": {"values": [0.35, 1.9]}}, **extra)
    raw["engagement"]["parameters"].update(section.get("parameters", {}))
    _expect(raw, key, "the study's default noise (friction_coefficient: scatter ±20 %)")
    raw["engagement"]["parameters"].pop("friction_coefficient")
    raw["engagement"]["friction_table"] = {
        "slip_speed": ["0 rad/s", "400 rad/s"],
        "friction_coefficient": [0.45, 0.40],
    }
    _expect(raw, key, "cannot scatter with a friction_table")


@pytest.mark.parametrize(
    "name, bounds, unit",
    [
        ("load_torque", ("40 N*m", "50 N*m"), "N m"),
        ("ambient_temperature", ("20 degC", "50 degC"), "K"),
    ],
)
def test_a_percent_sd_beside_absolute_bounds_is_refused_saying_what_to_write(name, bounds, unit):
    """`sd: '10 %'` beside min and max in the parameter's unit: a relative spread of an absolute
    noise (it was told "'10 %' is a ratio, a count or an angle"); told to give sd in the unit."""
    spec = {"dist": "normal", "sd": "10 %", "min": bounds[0], "max": bounds[1]}
    raw = {
        "studies": ["engagement"],
        "engagement": {
            "design": "factorial",
            "parameters": {"ramp_time": {"values": ["0.1 s", "0.2 s"]}},
            "noise": {name: spec},
            "noise_samples": 4,
        },
    }
    with pytest.raises(ConfigError) as err:
        config.resolve(raw)
    msg = str(err.value)
    assert f"engagement.noise.{name}.sd" in msg and "relative spread beside absolute bounds" in msg
    assert f"give sd in {unit}" in msg and "\n" not in msg
    raw["engagement"]["noise"][name]["sd"] = "2 K" if unit == "K" else "2 N*m"
    assert config.resolve(raw)["engagement"]["robust"]["noise"][name]["sd"] == pytest.approx(2.0)
