#!/bin/sh
# Install clutchsim (editable) with the extras EXTRAS into the virtual environment VENV,
# made with `python -m venv --without-pip` (ensurepip alone takes ~6 s):
#
#   scripts/venv-install.sh PYTHON VENV EXTRAS [compile]
#
# uv installs in parallel: the demo's packages (extras "plot") took ~4 s where pip took
# ~22 s, from an empty package cache (session 31); uv puts pip into the venv too, for the
# user.  Where uv cannot be installed or cannot reach an index (it does not read pip's
# configuration), pip installs instead, the same packages.  "compile" compiles every
# installed module's bytecode (the test suite's ~1,700 imports); without it the
# interpreter writes each module's on its first import.
set -u
py=$1 venv=$2 extras=$3 compile=${4:-}
uv_opt="" pip_opt="--no-compile"
if [ "$compile" = compile ]; then uv_opt="--compile-bytecode" pip_opt=""; fi

if "$py" -m pip --python "$venv/bin/python" install --quiet --disable-pip-version-check uv \
        && "$venv/bin/python" -m uv pip install --quiet --python "$venv/bin/python" $uv_opt \
            pip -e ".[$extras]"; then
    exit 0
fi
echo "uv could not install here: installing with pip" >&2
"$venv/bin/python" -m ensurepip --upgrade >/dev/null || exit 1
exec "$venv/bin/python" -m pip install --quiet --disable-pip-version-check $pip_opt -e ".[$extras]"
