#!/usr/bin/env bash
# Memcheck leg: run every Fortran test program (meson suite
# "fortran", CVODE tests and their failure paths included) under
#   valgrind --tool=memcheck --leak-check=full
# and print a summary: per program the exit status, the memcheck error count
# and the definitely-lost bytes.  Exits non-zero on any memcheck error, any
# definite (or indirect) leak, or a failing test.  "still reachable" blocks
# (the gfortran runtime's unit table, libc buffers) are not leaks and pass.
#
# Usage: tools/memcheck.sh [BUILD_DIR]     (default: build/memcheck)
# Environment:
#   MEMCHECK_BUILDTYPE  meson buildtype of a new build dir (default:
#                       debugoptimized: -O2 -g, the code users run, with lines)
#   MEMCHECK_SUITES     meson suites to run (default: "fortran")
#   MEMCHECK_ONLY       space-separated test names to restrict the run
#   MEMCHECK_JOBS       programs under valgrind at once (default: the cores)
#   PENDULA_TEST_QUICK  exported as 1 unless already set: Fortran tests that
#                       honour it run a reduced sweep (valgrind is ~30x slower)
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
bdir=${1:-build/memcheck}
case "$bdir" in /*) ;; *) bdir="$here/$bdir" ;; esac
buildtype=${MEMCHECK_BUILDTYPE:-debugoptimized}
suites=${MEMCHECK_SUITES:-fortran}
export PENDULA_TEST_QUICK=${PENDULA_TEST_QUICK:-1}
command -v valgrind >/dev/null || { echo "memcheck: valgrind not found (apt-get install valgrind)" >&2; exit 2; }
mkdir -p "$(dirname "$bdir")"

t0=$(date +%s)
if [ ! -f "$bdir/build.ninja" ]; then
  echo "memcheck: configuring $bdir (buildtype=$buildtype, -Dpython=disabled)"
  meson setup "$bdir" "$here" -Dpython=disabled -Dbuildtype="$buildtype" \
      >"$bdir.setup.log" 2>&1 \
    || { cat "$bdir.setup.log" >&2; echo "memcheck: meson setup FAILED" >&2; exit 2; }
fi
if ! ninja -C "$bdir" >"$bdir.ninja.log" 2>&1; then
  # The compiler's errors, not the pages of warnings around them.
  grep -E -A6 '^FAILED:|Error:|error:' "$bdir.ninja.log" | head -60 >&2
  echo "memcheck: build FAILED (log: $bdir.ninja.log)" >&2
  exit 2
fi
echo "memcheck: built in $(( $(date +%s) - t0 )) s"

# The test programs, their arguments, environment and working directory, as
# meson registered them (one tab-separated line per test).
list=$(cd "$bdir" && python3 - "$suites" "${MEMCHECK_ONLY:-}" <<'PY'
import json, subprocess, sys, shlex
suites = set(sys.argv[1].split())
only = set(sys.argv[2].split())
tests = json.loads(subprocess.check_output(["meson", "introspect", "--tests"]))
for t in tests:
    tsuites = {s.split(":")[-1] for s in t["suite"]}
    if not (tsuites & suites) or (only and t["name"] not in only):
        continue
    # Only compiled programs: valgrinding a wrapper script would check bash.
    with open(t["cmd"][0], "rb") as f:
        if f.read(4) != b"\x7fELF":
            continue
    env = " ".join(shlex.quote(f"{k}={v}") for k, v in (t.get("env") or {}).items())
    # Fields separated by \x1f: a tab would collapse empty fields in `read`.
    print("\x1f".join([t["name"], t.get("workdir") or ".", env or "-", shlex.join(t["cmd"])]))
PY
)
if [ -z "$list" ]; then
  echo "memcheck: no tests in suite(s) '$suites'" >&2
  exit 2
fi

logdir="$bdir/memcheck-logs"
rm -rf "$logdir"; mkdir -p "$logdir"
supp=()
[ -f "$here/tools/valgrind.supp" ] && supp=(--suppressions="$here/tools/valgrind.supp")
# One program under valgrind; its row of the summary goes to $logdir/$name.row.
check_one() {
  local name=$1 workdir=$2 envs=$3 cmd=$4 log="$logdir/$1.log" ts rc errors definite indirect
  [ "$envs" = - ] && envs=
  ts=$(date +%s)
  set +e
  (cd "$bdir" && cd "$workdir" && eval "env $envs valgrind --tool=memcheck --leak-check=full \
      --show-leak-kinds=definite,indirect --errors-for-leak-kinds=definite,indirect \
      --track-origins=yes --error-exitcode=99 --log-file=$(printf %q "$log") ${supp[*]:-} $cmd" \
      >"$logdir/$name.out" 2>&1)
  rc=$?
  set -e
  errors=$(sed -n 's/.*ERROR SUMMARY: \([0-9,]*\) errors.*/\1/p' "$log" 2>/dev/null | tr -d , | tail -n 1) || true
  definite=$(sed -n 's/.*definitely lost: \([0-9,]*\) bytes.*/\1/p' "$log" 2>/dev/null | tr -d , | tail -n 1) || true
  indirect=$(sed -n 's/.*indirectly lost: \([0-9,]*\) bytes.*/\1/p' "$log" 2>/dev/null | tr -d , | tail -n 1) || true
  echo "$rc ${errors:-?} ${definite:-0} ${indirect:-0} $(( $(date +%s) - ts ))" >"$logdir/$name.row"
}

# The programs run MEMCHECK_JOBS at a time (default: one per core; valgrind
# runs a program's threads on one core, so the leg was one core's work).
jobs=${MEMCHECK_JOBS:-$(nproc 2>/dev/null || echo 1)}
names=()
while IFS=$'\x1f' read -r name workdir envs cmd; do
  names+=("$name")
  while [ "$(jobs -rp | wc -l)" -ge "$jobs" ]; do wait -n || true; done
  check_one "$name" "$workdir" "$envs" "$cmd" </dev/null &
done <<<"$list"
wait

fail=0
summary=$(printf '%-28s %6s %8s %14s %14s %8s\n' program exit errors definitely indirectly seconds)
for name in "${names[@]}"; do
  read -r rc errors definite indirect secs <"$logdir/$name.row" || { rc=? errors=? definite=? indirect=? secs=?; }
  summary+=$(printf '\n%-28s %6s %8s %14s %14s %8s' "$name" "$rc" "$errors" "$definite" "$indirect" "$secs")
  if [ "$rc" != 0 ] || [ "$errors" != 0 ] || [ "$definite" != 0 ] || [ "$indirect" != 0 ]; then
    fail=1
    echo "memcheck: $name FAILED (exit $rc, $errors errors, $definite bytes definitely lost); log: $logdir/$name.log" >&2
    grep -E '^==[0-9]+== (Invalid|Conditional|Use of|Syscall|Mismatched|Source and|Argument)|definitely lost in|indirectly lost in' \
      "$logdir/$name.log" 2>/dev/null | head -20 >&2 || true
    tail -5 "$logdir/$name.out" >&2 || true
  fi
done
echo "memcheck summary (valgrind $(valgrind --version | sed 's/valgrind-//'), logs in $logdir):"
echo "$summary"
echo "memcheck: $( [ $fail -eq 0 ] && echo PASSED || echo FAILED ) in $(( $(date +%s) - t0 )) s"
exit $fail
