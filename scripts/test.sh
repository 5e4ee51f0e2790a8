#!/usr/bin/env bash
# Every test of the project, in the order a failure is cheapest to find.
set -euo pipefail
cd "$(dirname "$0")/.."
export PATH="$HOME/.cargo/bin:$PATH"
step() { printf '\n== %s\n' "$*" >&2; }

bash scripts/setup.sh --browser

step "formatting"
cargo fmt --check

step "the binding layer stays in src/wasm/"
if grep -rln "wasm_bindgen" src | grep -v '^src/wasm/' | grep -v '^src/lib.rs$'; then
  echo "wasm_bindgen is used outside src/wasm/ (files above)" >&2; exit 1
fi

step "no circular imports between the modules of src/wasm/"
node scripts/wasm-deps.mjs

step "clippy (native, and with the wasm feature)"
cargo clippy --all-targets -- -D warnings
cargo clippy --all-targets --features wasm -- -D warnings

step "docs"
RUSTDOCFLAGS="-D warnings" cargo doc --no-deps --document-private-items --quiet

step "native tests"
cargo test

step "the same tests as WebAssembly in Node"
wasm-pack test --node -- --features wasm

step "build the site"
node scripts/build.mjs

step "JavaScript API in Node, and the page in headless Chromium"
node --test --test-concurrency=1 tests/node/ tests/e2e/
