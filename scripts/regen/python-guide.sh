#!/usr/bin/env bash
# The figure of docs/guide/python.md: runs every ```python block of the page, in order, in one
# interpreter from the repository's root, so that the page's code is what makes its image
# (the last block writes docs/guide/python-equal-time.png). Uses target/python-venv, made by
# scripts/python-package.sh (run first where it is missing), with matplotlib added.
set -euo pipefail
cd "$(dirname "$0")/../.."
venv="$(realpath -m "${SPPM_PYTHON_VENV:-${CARGO_TARGET_DIR:-target}/python-venv}")"
[ -x "$venv/bin/python" ] && "$venv/bin/python" -c 'import sppm_gpu' 2>/dev/null || bash scripts/python-package.sh
"$venv/bin/python" -c 'import matplotlib' 2>/dev/null || "$venv/bin/python" -m pip install --quiet matplotlib==3.11.2
"$venv/bin/python" - <<'PY'
import re
text = open("docs/guide/python.md").read()
code = "\n".join(re.findall(r"```python\n(.*?)```", text, re.S))
exec(compile(code, "docs/guide/python.md", "exec"), {})
PY
