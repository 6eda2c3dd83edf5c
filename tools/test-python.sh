#!/usr/bin/env bash
# test-python.sh [VENV] - install the Python package into a virtual
# environment (made with the system's numpy and pytest, no network) and run
# its tests: what the README tells a Python user to do. VENV defaults to
# build/python-venv. The Debian interpreter (/usr/bin/python3) is preferred:
# python3-numpy and python3-pytest are installed for it.
set -euo pipefail
top=$(cd "$(dirname "$0")/.." && pwd)
venv=${1:-$top/build/python-venv}
py=python3
[ -x /usr/bin/python3 ] && py=/usr/bin/python3
[ -x "$venv/bin/python" ] || "$py" -m venv --system-site-packages "$venv"
# --no-index: everything comes from Debian (numpy through the system site
# packages); pip never reaches for the network, even where there is none.
"$venv/bin/python" -m pip install -q --no-index --disable-pip-version-check --no-build-isolation "$top/python"
cd "$top"
"$venv/bin/python" -m pytest -q python/tests
