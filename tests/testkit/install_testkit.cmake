# cmake -DPYTHON=… -DSOURCE=clients/python -DWORK=<dir> -P install_testkit.cmake
# Installs the test kit as a user would on Debian 12, offline: a venv that sees Debian's packages,
# Debian's pip, no package index, no build isolation (the build backend is Debian's setuptools).
# The package is copied out of the source tree first, so that the build leaves nothing behind there
# and the copy proves the package is self-contained.
foreach(var PYTHON SOURCE WORK)
  if(NOT DEFINED ${var})
    message(FATAL_ERROR "install_testkit.cmake needs -D${var}=…")
  endif()
endforeach()
file(REMOVE_RECURSE "${WORK}/venv" "${WORK}/src")
file(COPY "${SOURCE}/" DESTINATION "${WORK}/src" PATTERN build EXCLUDE PATTERN "*.egg-info" EXCLUDE
     PATTERN __pycache__ EXCLUDE)
execute_process(COMMAND "${PYTHON}" -m venv --without-pip --system-site-packages "${WORK}/venv"
                COMMAND_ERROR_IS_FATAL ANY)
set(ENV{PIP_FIND_LINKS} "")
execute_process(COMMAND "${PYTHON}" -m pip --python "${WORK}/venv/bin/python" install --no-index
                        --no-build-isolation --no-cache-dir "${WORK}/src"
                COMMAND_ERROR_IS_FATAL ANY)
