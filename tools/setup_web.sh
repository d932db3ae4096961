#!/usr/bin/env bash
# Installs what the browser test of the lightmap loaders needs (tests/web): Chromium and
# Node.js from Debian's packages, and three.js, Babylon.js and playwright-core at the versions
# tests/web/package-lock.json pins, from the npm registry.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
packages=()
command -v chromium >/dev/null || packages+=(chromium)
command -v node >/dev/null || packages+=(nodejs)
command -v npm >/dev/null || packages+=(npm)
if ((${#packages[@]})); then
  echo "setup_web: installing ${packages[*]}"
  sudo_cmd=""; [ "$(id -u)" -eq 0 ] || sudo_cmd="sudo"
  $sudo_cmd apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo_cmd apt-get install -y -qq --no-install-recommends "${packages[@]}" >/dev/null
fi
web="$root/tests/web"
# Reinstalled only when the lock file changed since the last install.
stamp="$web/node_modules/.radbake-lock"
if [[ ! -f "$stamp" ]] || ! cmp -s "$stamp" "$web/package-lock.json"; then
  echo "setup_web: npm ci in tests/web"
  (cd "$web" && npm ci --no-audit --no-fund --loglevel=error)
  cp "$web/package-lock.json" "$stamp"
fi
