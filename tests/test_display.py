"""The one table of display units (clutchlab.display): every unit a page or CSV shows converts back
to SI exactly as pint reads it in a config (the reference: pint's own conversion), temperatures
absolute in degC and differences in K, and the constraint echo in the unit a user would write."""

import numpy as np
import pytest
import xarray as xr

from clutchlab import display
from clutchlab.units import to_si


@pytest.mark.parametrize("si", sorted(k for k in display.TABLE if k != "1"))
def test_every_display_unit_reads_back_as_a_config_would(si):
    """A number shown in a display unit, written into a config with the CSV header's spelling,
    is the stored SI value again (pint, relative 1e-12)."""
    u = display.unit(si)
    for x in (1.0, 0.0023, 1848.0, 3.041e9):
        shown = u(x)
        assert to_si(f"{shown!r} {u.text}", si.replace("(m^2 K)", "(m^2*K)")) == pytest.approx(
            x, rel=1e-12
        )


def test_engineering_units_of_the_issue():
    """What the user read in SI (0.0028 m, 1.806e+09 Pa, 473.15 K) as engineers read it."""
    assert display.text(0.0028, display.unit("m")) == "2.8 mm"
    assert display.text(1.806e9, display.unit("Pa")) == "1806 MPa"
    assert display.text(473.15, display.unit("K", "peak_surface_temperature")) == "200 °C"
    assert display.text(np.deg2rad(57.5), display.unit("rad")) == "57.5 deg"
    assert display.text(5500 * np.pi / 30, display.unit("rad/s")) == "5500 rpm"
    assert display.text(173.0, display.unit("N m")) == "173 N·m"
    assert display.text(0.021, display.unit("kg m^2")) == "0.021 kg·m²"
    assert display.text(6146.0, display.unit("J")) == "6.146 kJ"
    assert display.text(3.7, display.unit("N", "spring_force")) == "3.7 N"  # a few newtons stay N
    assert display.text(2.5e3, display.unit("N", "clamp_load")) == "2.5 kN"


def test_temperatures_absolute_or_difference():
    """An absolute temperature in degC (offset -273.15), a difference (a rise) in K; the variable's
    CF units_metadata attribute wins over the name."""
    assert display.unit("K", "ambient_temperature").text == "degC"
    assert display.unit("K", "bulk_temperature_rise").text == "K"
    assert display.unit("K", "bulk_temperature_rise")(2.29) == 2.29
    assert display.unit("K", "anything", kind="difference").text == "K"
    assert display.unit("K", "x_rise", kind="absolute")(273.15) == pytest.approx(0.0, abs=1e-12)
    ds = xr.Dataset(
        {
            "a_rise": ((), 1.0, {"units": "K", "units_metadata": "temperature: on_scale"}),
            "b": ((), 1.0, {"units": "K", "units_metadata": "temperature: difference"}),
        }
    )
    assert display.unit_of(ds, "a_rise").text == "degC" and display.unit_of(ds, "b").text == "K"
    u = display.unit("K", "peak_surface_temperature")  # written back into a config, pint reads it
    assert to_si(f"{u(473.15)!r} {u.text}", "K", kind="absolute") == pytest.approx(
        473.15, rel=1e-14
    )


def test_constraint_echo_and_csv_columns():
    """The limit printed as the user wrote it (not max:473.15); CSV headers carry the unit."""
    assert display.limit_text("peak_surface_temperature", "max", 473.15, "K") == (
        "peak_surface_temperature max: 200 degC"
    )
    assert (
        display.limit_text("contact_stress", "max", 3041e6, "Pa") == "contact_stress max: 3041 MPa"
    )
    assert display.limit_text("lockup_time", "max", 0.5, "s") == "lockup_time max: 500 ms"
    assert display.column("sheet_thickness", display.unit("m")) == "sheet_thickness [mm]"
    assert display.column("torque", display.unit("N m")) == "torque [N*m]"
    assert display.column("friction_coefficient", display.unit("1")) == "friction_coefficient [-]"


def test_validation_rows_in_engineers_units():
    """A row of the validation table given in an SI unit is shown in the table's unit; a paper's
    own unit (MPa, deg, ms) as it is."""
    assert display.reported([8.9e6, 8.9666e6], "Pa") == ([8.9, pytest.approx(8.9666)], "MPa")
    (v,), u = display.reported([570.0], "rad s-1")
    assert u == "rpm" and v == pytest.approx(570.0 * 30 / np.pi, rel=1e-15)
    assert display.reported([2865.5], "MPa") == ([2865.5], "MPa")
    assert display.reported([1.25], "1") == ([1.25], "1")
