"""``hairbed solve`` with a pump drive: --pi/--q and, with a bed, --pressure-gradient and
--flow-rate, against the library's states (the physics is tested in test_channel_drives)."""

from __future__ import annotations

import json

import pytest

import hairbed
from hairbed.cli import main

BED_KW = dict(
    length=1e-3,
    radius=50e-6,
    youngs_modulus=1e6,
    channel_height=2e-3,
    viscosity=1.0,
    spacing=400e-6,
    base_angle=0.2,
)
BED_ARGS = [f"--{k.replace('_', '-')}={v}" for k, v in BED_KW.items()]


def _run(capsys, *args: str) -> tuple[int, str, str]:
    status = main(["solve", *args])
    out, err = capsys.readouterr()
    return status, out, err


@pytest.mark.parametrize("drive", ["pi", "q"])
def test_dimensionless_pump_drive(capsys, drive: str) -> None:
    status, out, err = _run(capsys, "--omega2=0.3", "--eps=0.6", "--theta0=0.4", f"--{drive}=2")
    assert status == 0 and err == ""
    status, out, err = _run(
        capsys, "--omega2=0.3", "--eps=0.6", "--theta0=0.4", f"--{drive}=2", "--json"
    )
    doc = json.loads(out)
    st = hairbed.solve_loaded(0.3, 0.6, 0.4, **{drive: 2.0})
    assert doc["tip_deflection"] == st.tip_deflection and doc["status"] == 0
    assert doc["drive"] == ("pressure" if drive == "pi" else "flow")


@pytest.mark.parametrize(
    ("option", "keyword"), [("--pressure-gradient=2e4", "pressure_gradient"),
                            ("--flow-rate=1e-6", "flow_rate")]
)  # fmt: skip
def test_bed_pump_drive(capsys, option: str, keyword: str) -> None:
    status, out, err = _run(capsys, *BED_ARGS, option, "--velocity=0.01", "--json")
    assert status == 0 and err == ""
    doc = json.loads(out)
    value = float(option.split("=")[1])
    st = hairbed.HairBed(**BED_KW).deform(0.01, **{keyword: value})
    assert doc["tip_deflection_m"] == st.tip_deflection
    assert doc["flow_rate_m^2/s"] == st.flow_rate
    assert doc["solution"]["status"] == 0


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["--eps=0.5", "--pi=1", "--q=1"], "at most one pump drive"),
        (["--pi=1"], "give --eps with --pi or --q"),
        (["--pressure-gradient=3"], "--pressure-gradient needs the physical inputs"),
        (["--eps=0.5", "--pi=1", "--all-branches"], "--pi and --q solve the physical state"),
        ([*BED_ARGS, "--pi=1"], "with a bed, give --pressure-gradient"),
        ([*BED_ARGS, "--flow-rate=1e-6", "--plot=x.png"], "not with a pump drive"),
        (["--eps=0", "--pi=1"], "eps"),
    ],
)
def test_errors_are_one_line(capsys, args: list[str], message: str) -> None:
    status, out, err = _run(capsys, *args)
    assert status == 2 and out == ""
    lines = err.strip().splitlines()
    assert len(lines) == 1 and message in lines[0], err


def test_sweep_over_a_pressure_gradient_is_the_library_sweep(tmp_path) -> None:
    xr = pytest.importorskip("xarray")
    out = tmp_path / "pumped.nc"
    status = main(
        ["sweep", *BED_ARGS, "--pressure-gradient=10:1e4:4:log", "--velocity=0,0.01",
         f"--out={out}"]
    )  # fmt: skip
    assert status == 0
    got = xr.open_dataset(out)
    want = hairbed.HairBed(**BED_KW).sweep(
        [0.0, 0.01], pressure_gradient=[10.0, 100.0, 1000.0, 10000.0]
    )
    assert got.tip_deflection.dims == ("velocity", "pressure_gradient")
    assert got.tip_deflection.values.tolist() == want.tip_deflection.values.tolist()
    assert got.attrs["drive"] == "pressure_gradient"


@pytest.mark.parametrize(
    ("args", "message"),
    [
        ([*BED_ARGS, "--flow-rate=1e-6", "--pressure-gradient=1"], "at most one pump drive"),
        (["--eps=0.5", "--omega2=1", "--flow-rate=1e-6"], "--flow-rate needs the physical"),
        ([*BED_ARGS, "--flow-rate=1e-6", "--wall-shear-stress=1"], "with a pump drive"),
    ],
)
def test_sweep_errors_are_one_line(capsys, args: list[str], message: str) -> None:
    status = main(["sweep", *args])
    out, err = capsys.readouterr()
    assert status == 2 and out == ""
    lines = err.strip().splitlines()
    assert len(lines) == 1 and message in lines[0], err
