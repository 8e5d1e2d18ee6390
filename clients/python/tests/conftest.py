# The kit's own tests. The plugin under test comes from the installed package (pytest11 entry
# point); pytester runs inner pytest sessions for the hook and fixture tests.
import pytest

from mcemu_testkit import find_binary
from mcemu_testkit.plugin import _binary

pytest_plugins = ["pytester"]


@pytest.fixture
def mcemu_bin(request):
    """The binary the outer session uses, passed on to inner pytester sessions."""
    return find_binary(_binary(request.config))
