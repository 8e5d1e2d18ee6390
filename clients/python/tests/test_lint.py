"""The master lint through the kit (docs/lint.md, docs/testkit.md): ``drive.lint()``, and strict tests
(``--mcemu-strict``, ``@pytest.mark.mcemu_strict``) that fail on a warn- or error-level finding with
the findings in the report."""
import pytest

SLOPPY_AND_CAREFUL = """
    import pytest

    def test_sloppy(mcemu_drive):
        rg = mcemu_drive.refgo()
        rg.ow(0x6040, 0, 15)        # Enable operation from Switch on disabled: the drive ignores it

    def test_careful(mcemu_drive):
        rg = mcemu_drive.refgo()
        for cw in (6, 7, 15):       # Shutdown, Switch on, Enable operation
            rg.ow(0x6040, 0, cw)
        rg.ow(0x6040, 0, 6)
"""


def test_drive_lint_returns_the_findings(mcemu_drive):
    rg = mcemu_drive.refgo()
    assert mcemu_drive.lint() == []
    rg.ow(0x6040, 0, 15)
    findings = mcemu_drive.lint(reset=True)
    assert [f["rule"] for f in findings] == ["cia402.command_ignored"]
    f = findings[0]
    assert (f["severity"], f["origin"]) == ("warn", "refgo")
    assert f["detail"] == "controlword 0x000F (Enable operation) in Switch on disabled is ignored"
    assert f["advice"].startswith("step through the states")
    assert "drive-core.md §4.2" in f["reference"]
    assert mcemu_drive.lint() == []  # reset
    report = mcemu_drive.api.lint()
    assert report["mode"] == "warn" and report["totals"]["warn"] == 0


def test_strict_option_fails_the_sloppy_test_with_its_findings(pytester, mcemu_bin):
    pytester.makepyfile(SLOPPY_AND_CAREFUL)
    result = pytester.runpytest("--mcemu-bin", mcemu_bin, "--mcemu-strict")
    result.assert_outcomes(failed=1, passed=1)
    result.stdout.fnmatch_lines([
        "*_ test_sloppy _*",
        "*mcemu strict: the drives reported 1 warn/error-level master-lint finding (docs/lint.md):",
        "*drive 1: cia402.command_ignored warn: controlword 0x000F (Enable operation) in Switch on disabled is "
        "ignored — step through the states* (at * ms, refgo, conn *)",
        "*- mcemu 1 log (call) -*",
    ])
    assert "[drive-core.md §4.2, §4.3; CiA 402-2" in result.stdout.str()  # the reference
    assert "test_careful" not in result.stdout.str().split("short test summary")[0].split("FAILURES")[-1]


def test_without_strict_the_findings_do_not_fail(pytester, mcemu_bin):
    pytester.makepyfile(SLOPPY_AND_CAREFUL)
    result = pytester.runpytest("--mcemu-bin", mcemu_bin)
    result.assert_outcomes(passed=2)


def test_the_marker_and_the_exemption(pytester, mcemu_bin):
    pytester.makepyfile("""
        import pytest

        @pytest.mark.mcemu_strict
        def test_marked(mcemu_drive):
            mcemu_drive.refgo().ow(0x6040, 0, 7)    # Switch on from Switch on disabled: ignored

        @pytest.mark.mcemu_strict(False)
        def test_exempt(mcemu_drive):
            mcemu_drive.refgo().ow(0x6040, 0, 7)

        @pytest.mark.mcemu_strict
        def test_info_level_is_not_a_failure(mcemu_drive):
            rg = mcemu_drive.refgo()
            for _ in range(20):                     # faster than a real drive answers: info only
                rg.tp()
    """)
    result = pytester.runpytest("--mcemu-bin", mcemu_bin, "--mcemu-strict", "-rA")
    result.assert_outcomes(failed=1, passed=2)
    result.stdout.fnmatch_lines(["*_ test_marked _*", "mcemu strict: the drives reported 1 warn/error-level*",
                                 "FAILED *::test_marked*"])


@pytest.mark.mcemu(config={"lint": {"rules": {"cia402.command_ignored": "error"}}})
def test_error_level_from_the_config(mcemu_drive):
    mcemu_drive.refgo().ow(0x6040, 0, 7)
    (f,) = mcemu_drive.lint()
    assert f["severity"] == "error"
    assert mcemu_drive.api.lint()["totals"]["failing"] == 1
