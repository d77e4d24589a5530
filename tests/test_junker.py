"""The Junker study (studies/junker.py): the loosening's joint on a flexible shank shaken across at the
plate. Its quick form's oracles: the critical amplitude against the guided beam's closed form on the
beam elements and on the lumped shank, the shear's compliance between them, the elements' count, and
the loosening rate above and below the onset."""
import pytest


def test_junker_study_quick(tmp_path, quick_study):
    """studies/junker.py --quick: the bracketed critical amplitude within 1 % of the guided beam's closed
    form at mu 0.12 (the default joint) on the beam elements and on the lumped shank, the shear's
    compliance raising the elements' onset and one element's onset as two's; on the square thread the
    nut turns loose above it and holds below, on the 60 degree thread it holds."""
    from exu_aniso.util.output import read_table
    quick_study("junker", tmp_path)
    C = read_table(tmp_path / "critical_amplitude.csv")
    at = {(shank, mu): (m, e) for shank, mu, m, e in zip(C["shank [-]"], C["mu [-]"], C["measured [m]"],
                                                         C["error [-]"])}
    assert abs(at[("fe_beam", 0.12)][1]) < 1e-2 and abs(at[("guided_beam", 0.12)][1]) < 1e-2
    assert at[("fe_beam", 0.12)][0] > 1.1 * at[("guided_beam", 0.12)][0]      # the shear's compliance
    E = read_table(tmp_path / "shank_elements.csv")
    assert E["measured [m]"][1] == pytest.approx(E["measured [m]"][0], rel=1e-6)
    R = read_table(tmp_path / "loosening_rate.csv")
    rate = {(b, a): r for b, a, r in zip(R["flank_angle [deg]"], R["amplitude [m]"], R["rotation_per_cycle [rad]"])}
    assert rate[(0.0, 1.1e-4)] > 1e-3 > 1e-6 > abs(rate[(0.0, 6e-5)])
    assert abs(rate[(60.0, 1.1e-4)]) < 1e-6
    assert all(R["energy_ok [-]"])
    assert "python studies/junker.py" in (tmp_path / "report.md").read_text()
