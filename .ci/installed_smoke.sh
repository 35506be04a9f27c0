#!/usr/bin/env bash
# The README's commands against stampc installed as a regular (non-editable) wheel in a
# fresh virtual environment, run from a temporary folder outside the repository: with
# relative paths (from a copy of examples/, as in a fresh clone) and absolute ones. Any
# unexpected exit code fails the run, loudly, with the command's output.
#
#   .ci/installed_smoke.sh             # dependencies from PyPI (pip's cache is used)
#   STAMPC_SMOKE_SYSTEM_SITE=1 .ci/installed_smoke.sh   # reuse installed dependencies
set -euo pipefail
REPO="$(cd "$(dirname "$0")/.." && pwd)"
PYTHON="${PYTHON:-python3}"
WORK="$(mktemp -d "${TMPDIR:-/tmp}/stampc-smoke.XXXXXX")"
trap 'rm -rf "$WORK"' EXIT

echo "== building the wheel"
"$PYTHON" -m pip wheel --quiet --no-deps --wheel-dir "$WORK/dist" "$REPO"
WHEEL="$(ls "$WORK"/dist/stampc-*.whl)"

echo "== installing $(basename "$WHEEL") into a fresh virtual environment"
if [[ "${STAMPC_SMOKE_SYSTEM_SITE:-0}" == 1 ]]; then
    "$PYTHON" -m venv --system-site-packages "$WORK/venv"
    # --ignore-installed: an editable stampc in the system site must not satisfy it
    "$WORK/venv/bin/python" -m pip install --quiet --ignore-installed --no-deps "$WHEEL"
else
    "$PYTHON" -m venv "$WORK/venv"
    "$WORK/venv/bin/python" -m pip install --quiet "$WHEEL[view,lsp]"
fi
STAMPC="$WORK/venv/bin/stampc"
INSTALLED="$(cd "$WORK" && "$WORK/venv/bin/python" -c 'import stampc; print(stampc.__file__)')"
case "$INSTALLED" in
    "$WORK/venv/"*) echo "   stampc imported from $INSTALLED" ;;
    *) echo "FAIL: stampc is imported from $INSTALLED, not from the wheel in $WORK/venv" >&2
       exit 1 ;;
esac

CLONE="$WORK/clone"
mkdir -p "$CLONE" "$WORK/elsewhere"
cp -r "$REPO/examples" "$CLONE/examples"
find "$CLONE" -name __pycache__ -prune -exec rm -rf {} +
export MPLBACKEND=Agg

# expect CODE DIR ARGS...: run ARGS in DIR; fail unless it exits with CODE
expect() {
    local want="$1" dir="$2"
    shift 2
    echo "== (in ${dir#"$WORK"/}) $* ; expecting exit $want"
    local got=0
    (cd "$dir" && "$@") >"$WORK/out.log" 2>&1 || got=$?
    if [[ "$got" != "$want" ]]; then
        echo "FAIL: exit $got, expected $want: $*" >&2
        cat "$WORK/out.log" >&2
        exit 1
    fi
    tail -n 3 "$WORK/out.log" | sed 's/^/   /'
}

EX="$CLONE/examples"
expect 0 "$CLONE" "$STAMPC" --version
expect 0 "$CLONE" "$STAMPC" check examples/cluttered_table/domain.stamp
expect 0 "$WORK/elsewhere" "$STAMPC" check "$EX/cluttered_table/domain.stamp" "$EX/cluttered_table/problem.stamp"
expect 0 "$CLONE" "$STAMPC" fmt examples/domino/domain.stamp
expect 0 "$CLONE" "$STAMPC" compile examples/keva/domain.stamp examples/keva/problem.stamp --target ppddl -o out/
expect 0 "$CLONE" "$STAMPC" solve examples/domino/domain.stamp examples/domino/problem.stamp
TIREWORLD="$REPO/../shared/benchmarks/ppddl/ippc2006-tireworld/p03.pddl"
if [[ -f "$TIREWORLD" ]]; then  # the README's solve example, where the benchmarks exist
    expect 0 "$WORK/elsewhere" "$STAMPC" solve "$TIREWORLD" --unit-cost
fi
expect 0 "$WORK/elsewhere" "$STAMPC" refine "$EX/cluttered_table/domain.stamp" "$EX/cluttered_table/problem2d.stamp" \
       --world plane2d --time-limit 60 -o mobile2d/
expect 0 "$CLONE" "$STAMPC" refine examples/cluttered_table/domain_fixed.stamp examples/cluttered_table/problem2d_fixed.stamp \
       --world plane2d --time-limit 60 -o out2d/
expect 0 "$CLONE" "$STAMPC" refine examples/cluttered_table/domain.stamp examples/cluttered_table/problem.stamp \
       --world pybullet --time-limit 120 -o out/
expect 0 "$CLONE" "$STAMPC" execute out/policy.json --runs 50 --seed 1 --render out/frames
expect 0 "$CLONE" "$STAMPC" view out/
[[ -s "$CLONE/out/report.html" ]] || { echo "FAIL: stampc view wrote no out/report.html" >&2; exit 1; }
expect 0 "$WORK/elsewhere" "$STAMPC" execute "$CLONE/out2d/policy.json" --runs 5
expect 0 "$WORK/elsewhere" "$STAMPC" refine "$EX/domino/domain.stamp" "$EX/domino/problem.stamp" \
       --world pybullet --time-limit 60 -o "$WORK/elsewhere/out"
# the language server: initialize, shutdown and exit over stdio, as an editor does
cat > "$WORK/lsp_smoke.py" <<'PY'
import json, subprocess, sys
def frame(obj):
    body = json.dumps(obj).encode()
    return b"Content-Length: %d\r\n\r\n" % len(body) + body
messages = [
    {"jsonrpc": "2.0", "id": 1, "method": "initialize", "params": {"capabilities": {}}},
    {"jsonrpc": "2.0", "method": "initialized", "params": {}},
    {"jsonrpc": "2.0", "id": 2, "method": "shutdown"},
    {"jsonrpc": "2.0", "method": "exit"},
]
done = subprocess.run([sys.argv[1], "lsp"], input=b"".join(map(frame, messages)),
                      capture_output=True, timeout=60)
out = done.stdout.decode().replace('":', '": ').replace('":  ', '": ')
assert '"hoverProvider": true' in out and '"id": 2' in out, out[:500]
print("stampc lsp answered initialize and shutdown, exit", done.returncode)
sys.exit(done.returncode)
PY
expect 0 "$WORK/elsewhere" "$WORK/venv/bin/python" "$WORK/lsp_smoke.py" "$STAMPC"
expect 2 "$WORK/elsewhere" "$STAMPC" check no_such_file.stamp
expect 2 "$WORK/elsewhere" "$STAMPC" refine "$EX/domino/domain.stamp" --time-limit 0

# the README's "Python API" block, verbatim, as a script outside the repository
"$WORK/venv/bin/python" - "$REPO/README.md" "$WORK/snippet.py" <<'PY'
import sys
text = open(sys.argv[1], encoding="utf-8").read().split("## Python API", 1)[1]
open(sys.argv[2], "w", encoding="utf-8").write(text.split("```python\n", 1)[1].split("```", 1)[0])
PY
expect 0 "$CLONE" "$WORK/venv/bin/python" "$WORK/snippet.py"
echo "installed smoke test: all commands behaved as documented"
