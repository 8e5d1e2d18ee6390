"""The machine test of docs/testkit.md runs as written."""
import re
from pathlib import Path

DOC = Path(__file__).resolve().parents[3] / "docs" / "testkit.md"


def test_the_machine_test_of_the_docs(pytester, mcemu_bin):
    example = re.search(r"```python\n(.*?)```", DOC.read_text(), re.S).group(1)
    assert "def test_axis_1_moves_alone(mcemu_fleet)" in example
    pytester.makepyfile(test_machine=example)
    result = pytester.runpytest("--mcemu-bin", mcemu_bin, "-v")
    result.assert_outcomes(passed=1)
    result.stdout.fnmatch_lines(["*test_axis_1_moves_alone PASSED*"])
