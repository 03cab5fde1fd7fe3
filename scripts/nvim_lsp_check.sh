#!/bin/sh
# A real client: Neovim, headless, with editors/nvim/init.lua, opens a
# scene with a mistake, waits for `raytrace lsp` to publish its
# diagnostics, and prints what vim.diagnostic.get() holds (lnum is 0-based).
# Usage: scripts/nvim_lsp_check.sh [SCENE.rt]   (needs nvim; builds raytrace)
set -eu
here=$(cd "$(dirname "$0")/.." && pwd)
cargo build --quiet --manifest-path "$here/Cargo.toml"
export RAYTRACE="${RAYTRACE:-$here/target/debug/raytrace}"
scene=${1:-}
if [ -z "$scene" ]; then
  dir=$(mktemp -d)
  scene=$dir/mistake.rt
  printf 'camera { position <0, 1, 5>  look_at <0, 0, 0> }\nlight { position <5, 5, 5> }\n\nsphere { radus 1  material { colour red } }\n' > "$scene"
fi
echo "--- $scene"
cat -n "$scene"
echo "---"
nvim --headless -u "$here/editors/nvim/init.lua" "$scene" \
  -c 'lua vim.wait(10000, function() return #vim.diagnostic.get(0) > 0 end, 50)' \
  -c 'lua for _, d in ipairs(vim.diagnostic.get(0)) do print(string.format("line %d (lnum %d), col %d-%d, severity %d: %s", d.lnum + 1, d.lnum, d.col, d.end_col, d.severity, d.message:gsub("\n", " | "))) end' \
  -c 'lua if #vim.diagnostic.get(0) == 0 then print("no diagnostics") vim.cmd("cquit 1") end' \
  -c 'qa!' 2>&1
echo
