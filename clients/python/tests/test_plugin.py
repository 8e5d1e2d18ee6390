"""The pytest plugin itself: entry point, fixtures, markers, clean stop, log in failing reports."""


def test_failing_test_report_carries_the_log(pytester, mcemu_bin):
    pytester.makepyfile("""
        def test_fails(mcemu_drive):
            mcemu_drive.refgo().ow(0x6081, 0, 777)
            assert False, "on purpose"

        def test_passes(mcemu_drive):
            assert mcemu_drive.refgo().tp() == 0
    """)
    result = pytester.runpytest("--mcemu-bin", mcemu_bin)
    result.assert_outcomes(failed=1, passed=1)
    result.stdout.fnmatch_lines(["*_ test_fails _*", "*- mcemu 1 log (call) -*", "$ *mcemu --state-dir *",
                                 "*listening: refgo tcp 127.0.0.1:*", "*mcemu 0.1.0 ready*"])
    assert result.stdout.str().count("mcemu 1 log") == 1  # the passing test has none


def test_a_crash_fails_the_teardown_with_the_log(pytester, mcemu_bin):
    pytester.makepyfile("""
        def test_kills(mcemu_drive):
            mcemu_drive.process.proc.kill()
            mcemu_drive.process.proc.wait()
    """)
    result = pytester.runpytest("--mcemu-bin", mcemu_bin)
    result.assert_outcomes(passed=1, errors=1)
    result.stdout.fnmatch_lines(["*mcemu exited during the test with status -9*", "*- mcemu 1 log (teardown) -*"])


def test_start_up_failure_names_the_reason(pytester, mcemu_bin):
    pytester.makepyfile("""
        import pytest

        @pytest.mark.mcemu(model="NOPE")
        def test_bad_model(mcemu_drive):
            pass
    """)
    result = pytester.runpytest("--mcemu-bin", mcemu_bin)
    result.assert_outcomes(errors=1)
    result.stdout.fnmatch_lines(["*mcemu exited at start-up with status 2*", "*NOPE*"])


def test_marker_and_factory_options(pytester, mcemu_bin):
    pytester.makepyfile("""
        import pytest

        @pytest.mark.mcemu("--ip", "10.9.8.7", model="MCN23")
        def test_marker(mcemu_drive):
            assert (mcemu_drive.model, mcemu_drive.ip) == ("MCN23", "10.9.8.7")

        def test_default_fleet_has_two_drives(mcemu_fleet):
            assert len(mcemu_fleet) == 2

        def test_factory(mcemu_start):
            a, b = mcemu_start(), mcemu_start(model="MCFLAT")
            assert (a.drive(1).model, b.drive(1).model) == ("MC349", "MCFLAT")
            assert a.stop() == 0 and not a.running
    """)
    result = pytester.runpytest("--mcemu-bin", mcemu_bin, "--mcemu-log-level", "debug")
    result.assert_outcomes(passed=3)


def test_binary_from_the_environment_and_the_header(pytester, mcemu_bin, monkeypatch):
    pytester.makepyfile("def test_it(mcemu_drive):\n    assert mcemu_drive.process.binary == %r\n" % mcemu_bin)
    monkeypatch.setenv("MCEMU_BIN", mcemu_bin)
    result = pytester.runpytest_subprocess()  # a fresh interpreter: the plugin comes from its entry point
    result.assert_outcomes(passed=1)
    result.stdout.fnmatch_lines([f"mcemu: {mcemu_bin} (mcemu *)"])


def test_missing_binary_and_disabled_plugin(pytester):
    pytester.makepyfile("def test_it(mcemu_drive):\n    pass\n")
    result = pytester.runpytest("--mcemu-bin", "/nonexistent/mcemu")
    result.assert_outcomes(errors=1)
    result.stdout.fnmatch_lines(["*'/nonexistent/mcemu' does not exist or is not executable*"])
    result = pytester.runpytest("-p", "no:mcemu")
    result.stdout.fnmatch_lines(["*fixture 'mcemu_drive' not found*"])
