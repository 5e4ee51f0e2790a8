#!/usr/bin/env bash
# `npm run fuzz`: the mutation, parameter and planner fuzz tests of tests/fuzz.rs, natively
# in release mode, for SKINPATH_FUZZ_SECONDS (default 60) each, two at a time; prints the
# case counts per kind. SKINPATH_FUZZ_SEED=N explores another sequence; SKINPATH_FUZZ_CASES=N runs a
# fixed number of cases instead.
set -euo pipefail
cd "$(dirname "$0")/.."
if [ -z "${SKINPATH_FUZZ_CASES:-}" ]; then
  export SKINPATH_FUZZ_SECONDS="${SKINPATH_FUZZ_SECONDS:-60}"
fi
exec cargo test --release --test fuzz -- --nocapture --test-threads=2
