#!/usr/bin/env bash
# Idempotent set-up shared by `npm start`, `npm test` and `npm run bench`.
# Installs only what is missing: the wasm32 target, rustfmt/clippy, the pinned wasm-pack and
# wasm-bindgen-cli, the npm packages, and (with --browser) Debian's Chromium for the browser
# tests. When everything is present it takes well under a few seconds.
set -euo pipefail
cd "$(dirname "$0")/.."
# rustup's default install directory, often missing from PATH in a non-login shell.
export PATH="$HOME/.cargo/bin:$PATH"

WASM_PACK_VERSION=0.15.1
# The CLI must match the `wasm-bindgen = "=X"` pin in Cargo.toml exactly.
WASM_BINDGEN_VERSION=$(sed -n 's/^wasm-bindgen = { version = "=\([0-9.]*\)".*/\1/p' Cargo.toml)
want_browser=0
[ "${1:-}" = "--browser" ] && want_browser=1

say() { printf 'setup: %s\n' "$*" >&2; }

if ! command -v cargo >/dev/null 2>&1; then
  say "cargo is not installed; install Rust from rustup first"; exit 1
fi
if command -v rustup >/dev/null 2>&1; then
  rustup target list --installed | grep -qx wasm32-unknown-unknown \
    || { say "adding the wasm32-unknown-unknown target"; rustup target add wasm32-unknown-unknown; }
  for c in rustfmt clippy; do
    rustup component list --installed | grep -q "^$c" \
      || { say "adding rustup component $c"; rustup component add "$c"; }
  done
fi

if ! wasm-pack --version 2>/dev/null | grep -q " $WASM_PACK_VERSION\$"; then
  say "installing wasm-pack $WASM_PACK_VERSION (about two minutes)"
  cargo install wasm-pack --version "$WASM_PACK_VERSION" --force
fi
if ! wasm-bindgen --version 2>/dev/null | grep -q " $WASM_BINDGEN_VERSION\$"; then
  say "installing wasm-bindgen-cli $WASM_BINDGEN_VERSION (about two minutes)"
  # no --locked: the registry mirror lacks some of the versions its lock file names
  cargo install wasm-bindgen-cli --version "$WASM_BINDGEN_VERSION" --force
fi

# npm packages: reinstall when package.json or the lock changed since the last install.
stamp=node_modules/.skinpath-installed
if [ ! -f "$stamp" ] || [ package.json -nt "$stamp" ] || { [ -f package-lock.json ] && [ package-lock.json -nt "$stamp" ]; }; then
  say "installing npm packages"
  if [ -f package-lock.json ]; then npm ci --no-audit --no-fund; else npm install --no-audit --no-fund; fi
  touch "$stamp"
fi

if [ "$want_browser" = 1 ] && [ ! -x /usr/bin/chromium ]; then
  say "installing Debian's chromium for the browser tests"
  if [ "$(id -u)" = 0 ]; then
    apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq chromium >/dev/null
  elif command -v sudo >/dev/null 2>&1; then
    sudo apt-get update -qq && sudo DEBIAN_FRONTEND=noninteractive apt-get install -y -qq chromium >/dev/null
  else
    say "cannot install chromium without root: run 'apt-get install chromium' as root"; exit 1
  fi
fi
exit 0
