#!/usr/bin/env bash
# The test command of sprung (the README's, and what .ci/run calls): set up
# what the tests need, build the web viewer, run every test of the
# workspace (the doc examples and the viewer's tests in a real browser and
# a real X server included), then run every example program of the engine
# (crates/sprung/examples/*.rs, in the dev profile the tests build in,
# each given a temporary folder for its files), then build the Python
# package's wheel (maturin) into a virtual environment under target/,
# check its types and its extension's stubs (mypy, mypy.stubtest) and run
# its tests (pytest, python/tests): it fails if one fails.
#
#   scripts/test.sh                 everything
#   scripts/test.sh -- NAME         extra arguments go to `cargo test --workspace`
#
# Installs only what is missing:
#   - Debian packages (apt-get, as root or through sudo): chromium (the
#     browser test), xvfb (an X server without a screen, for the native
#     window) and the Mesa libraries that give it OpenGL in software
#     (libgl1, libglx-mesa0, libgl1-mesa-dri; libx11-6, libxi6 and
#     libxkbcommon0 are loaded by the windowing library at run time),
#     and Mesa's software Vulkan driver (mesa-vulkan-drivers, with the
#     loader libvulkan1) that runs the GPU step's tests on the CPU
#     (SPRUNG_GPU_TESTS=require: they fail, not skip, without it);
#   - the Rust target wasm32-unknown-unknown (rustup) and wasm-bindgen-cli
#     at the version of Cargo.lock's wasm-bindgen (cargo install, from
#     crates.io: scripts/build-web.sh installs both);
#   - Playwright (`npm ci` in crates/sprung-viewer/web-tests, from its
#     package-lock.json; it drives the Debian Chromium, it downloads no
#     browser);
#   - a virtual environment target/python-venv with maturin, numpy,
#     pytest, Pillow, pandas, Dask and mypy (python/requirements-test.txt,
#     from PyPI); the sweep's tests start a Dask scheduler and two workers on
#     127.0.0.1.
# Node.js 20 or newer and Python 3.9 or newer (python3, with its venv
# module) must be on the PATH (they are on the project's machines).
set -euo pipefail
cd "$(dirname "$0")/.."

packages=(chromium xvfb libgl1 libglx-mesa0 libgl1-mesa-dri libx11-6 libxi6 libxkbcommon0
  mesa-vulkan-drivers libvulkan1)
missing=()
for package in "${packages[@]}"; do
  if ! dpkg-query -W -f '${Status}' "$package" 2>/dev/null | grep -q "ok installed"; then
    missing+=("$package")
  fi
done
if ((${#missing[@]})); then
  echo "== apt-get install ${missing[*]}"
  sudo=()
  if [ "$(id -u)" -ne 0 ]; then
    command -v sudo >/dev/null || { echo "scripts/test.sh: installing ${missing[*]} needs root or sudo" >&2; exit 1; }
    sudo=(sudo)
  fi
  export DEBIAN_FRONTEND=noninteractive
  "${sudo[@]}" apt-get update -qq
  "${sudo[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi

if ! node -e 'process.exit(Number(process.versions.node.split(".")[0]) >= 20 ? 0 : 1)' 2>/dev/null; then
  echo "scripts/test.sh: the browser test needs Node.js 20 or newer (node on the PATH)" >&2
  exit 1
fi
echo "== npm ci (crates/sprung-viewer/web-tests)"
(cd crates/sprung-viewer/web-tests && npm ci --no-audit --no-fund --loglevel=error)

scripts/build-web.sh

echo "== the engine's rooms stack in floors (scripts/imports.py --check)"
python3 scripts/imports.py --check

echo "== cargo test --workspace"
SPRUNG_GPU_TESTS=require cargo test --workspace "$@"

# The examples take an output folder as their argument where they write
# files (flag.rs); the others ignore it.
examples_out=$(mktemp -d)
trap 'rm -rf "$examples_out"' EXIT
for example in crates/sprung/examples/*.rs; do
  name=$(basename "$example" .rs)
  echo "== cargo run -p sprung --example $name"
  cargo run -q -p sprung --example "$name" -- "$examples_out/$name"
done

echo "== python: maturin build, pytest python/tests"
venv=target/python-venv
if [ ! -x "$venv/bin/python" ]; then
  python3 -m venv "$venv"
fi
"$venv/bin/pip" install -q --disable-pip-version-check -r python/requirements-test.txt
rm -rf target/wheels
(cd python && "../$venv/bin/maturin" build -q --interpreter "../$venv/bin/python" -o ../target/wheels)
"$venv/bin/pip" install -q --disable-pip-version-check --force-reinstall --no-deps target/wheels/sprung-*.whl
echo "== python: the package and its stubs (mypy; mypy.stubtest against the wheel)"
(cd python && "../$venv/bin/python" -m mypy)
"$venv/bin/python" -m mypy.stubtest sprung._native
# The runs compared with the command line use the `sprung` that
# `cargo test` built.
SPRUNG_BIN="$PWD/target/debug/sprung" "$venv/bin/pytest" -q -p no:cacheprovider python/tests
