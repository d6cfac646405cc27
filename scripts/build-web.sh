#!/usr/bin/env bash
# Build the web viewer into target/web/ (a static page: serve the folder
# with any file server, e.g. `python3 -m http.server -d target/web 8000`):
#
#   index.html          crates/sprung-viewer/web/index.html
#   gl.js               macroquad's JavaScript loader, copied from the source
#                       of the miniquad crate this build uses (MIT/Apache-2.0,
#                       not kept in this repository)
#   sprung-viewer.wasm  the viewer built for wasm32-unknown-unknown, through
#                       wasm-bindgen (the GPU step's WebGPU calls)
#   sprung-viewer.js    wasm-bindgen's JavaScript for them, which index.html
#                       joins to gl.js's imports (macroquad's own, "env")
#
# wasm-bindgen-cli is installed with cargo at the version of the
# wasm-bindgen crate in Cargo.lock (the two must match) if it is missing.
set -euo pipefail
cd "$(dirname "$0")/.."

if ! rustup target list --installed 2>/dev/null | grep -qx wasm32-unknown-unknown; then
  echo "== rustup target add wasm32-unknown-unknown"
  rustup target add wasm32-unknown-unknown
fi

# The wasm-bindgen crate's version in Cargo.lock.
bindgen_version=$(python3 -c '
import re, sys
lock = open("Cargo.lock").read()
found = re.search(r"name = \"wasm-bindgen\"\nversion = \"([^\"]+)\"", lock)
sys.exit("build-web.sh: no wasm-bindgen in Cargo.lock") if not found else print(found.group(1))
')
if [ "$(wasm-bindgen --version 2>/dev/null)" != "wasm-bindgen $bindgen_version" ]; then
  echo "== cargo install wasm-bindgen-cli --version $bindgen_version"
  # --force: cargo may record an install whose binary is gone.
  cargo install --force wasm-bindgen-cli --version "$bindgen_version"
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
bindgen="$target_dir/web-bindgen"
rm -rf "$bindgen"
echo "== wasm-bindgen --target web"
wasm-bindgen --target web --no-typescript --out-dir "$bindgen" --out-name sprung-viewer \
  "$target_dir/wasm32-unknown-unknown/release/sprung-viewer.wasm"
# wasm-bindgen's module imports macroquad's functions from a module "env",
# which a browser cannot resolve: index.html gives it gl.js's instead. Its
# import lines go, and the functions that build the imports and take the
# instance are exported for the page.
python3 - "$bindgen/sprung-viewer.js" "$out/sprung-viewer.js" <<'PY'
import re, sys
source, target = sys.argv[1], sys.argv[2]
text = open(source).read()
text = re.sub(r'^import \* as import\d+ from "env";?\n', "", text, flags=re.M)
text = re.sub(r'^\s*"env": import\d+,?\n', "", text, flags=re.M)
for needed in ("function __wbg_get_imports(", "function __wbg_finalize_init("):
    if needed not in text:
        sys.exit(f"build-web.sh: wasm-bindgen's JavaScript has no {needed}...): another wasm-bindgen?")
if '"env"' in text:
    sys.exit('build-web.sh: wasm-bindgen\'s JavaScript still imports "env"')
text += "\n// Added by scripts/build-web.sh, for index.html's loader.\nexport { __wbg_get_imports, __wbg_finalize_init };\n"
open(target + ".partial", "w").write(text)
PY
mv "$out/sprung-viewer.js.partial" "$out/sprung-viewer.js"
cp "$bindgen/sprung-viewer_bg.wasm" "$out/sprung-viewer.wasm"
echo "built $out ($(du -h "$out/sprung-viewer.wasm" | cut -f1) of wasm)"
echo "serve it: python3 -m http.server -d $out 8000, then open http://127.0.0.1:8000/ (or .../#flag)"
