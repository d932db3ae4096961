#!/usr/bin/env bash
# The Khronos glTF validator (npm package gltf-validator) over radbake's .glb outputs:
#   tools/gltf_validate.sh FILE.glb...     (e.g. tools/gltf_validate.sh baked/*/*.glb)
# Installs nodejs/npm (apt) and the validator (npm, into ~/.cache/radbake-gltf-validator) when
# missing. Exit 1 when any file has an error or a warning. Not part of ctest: it needs npm's registry.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cache="${XDG_CACHE_HOME:-$HOME/.cache}/radbake-gltf-validator"
if ! command -v node >/dev/null || ! command -v npm >/dev/null; then
    sudo_cmd=""; [ "$(id -u)" -eq 0 ] || sudo_cmd="sudo"
    $sudo_cmd apt-get update -qq
    DEBIAN_FRONTEND=noninteractive $sudo_cmd apt-get install -y -qq --no-install-recommends nodejs npm >/dev/null
fi
if [[ ! -d "$cache/node_modules/gltf-validator" ]]; then
    mkdir -p "$cache"
    (cd "$cache" && npm install --silent --no-audit --no-fund gltf-validator >/dev/null)
fi
NODE_PATH="$cache/node_modules" exec node "$root/tools/gltf/validate.js" "$@"
