#!/usr/bin/env bash
# Build the web viewer into target/web/ (a static page: serve the folder
# with any file server, e.g. `python3 -m http.server -d target/web 8000`):
#
#   index.html          crates/sprung-viewer/web/index.html
#   gl.js               macroquad's JavaScript loader, copied from the source
#                       of the miniquad crate this build uses (MIT/Apache-2.0,
#                       not kept in this repository)
#   sprung-viewer.wasm  the viewer built for wasm32-unknown-unknown
set -euo pipefail
cd "$(dirname "$0")/.."

if ! rustup target list --installed 2>/dev/null | grep -qx wasm32-unknown-unknown; then
  echo "== rustup target add wasm32-unknown-unknown"
  rustup target add wasm32-unknown-unknown
fi

echo "== cargo build --release --target wasm32-unknown-unknown -p sprung-viewer"
# No debug line tables in the page: they would double the download.
CARGO_PROFILE_RELEASE_DEBUG=false \
  cargo build --release --target wasm32-unknown-unknown -p sprung-viewer

# Where cargo put it, and where the miniquad crate's source (with js/gl.js) is.
read -r target_dir miniquad_dir < <(
  cargo metadata --format-version 1 --filter-platform wasm32-unknown-unknown |
    python3 -c '
import json, os, sys
meta = json.load(sys.stdin)
dirs = [os.path.dirname(p["manifest_path"]) for p in meta["packages"] if p["name"] == "miniquad"]
if not dirs:
    sys.exit("build-web.sh: miniquad is not among the dependencies of the workspace")
print(meta["target_directory"], dirs[0])
')

out="$target_dir/web"
mkdir -p "$out"
cp crates/sprung-viewer/web/index.html "$out/index.html"
cp "$miniquad_dir/js/gl.js" "$out/gl.js"
cp "$target_dir/wasm32-unknown-unknown/release/sprung-viewer.wasm" "$out/sprung-viewer.wasm"
echo "built $out ($(du -h "$out/sprung-viewer.wasm" | cut -f1) of wasm)"
echo "serve it: python3 -m http.server -d $out 8000, then open http://127.0.0.1:8000/ (or .../#flag)"
