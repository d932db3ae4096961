#!/usr/bin/env bash
# Installs, from Debian 12's packages, whatever of radbake's build and test needs is missing.
set -euo pipefail
packages=(cmake ninja-build g++ pkg-config python3
          libassimp-dev libopenexr-dev libglm-dev libstb-dev doctest-dev
          libembree-dev libtbb-dev libcli11-dev zlib1g-dev libssl-dev nlohmann-json3-dev
          libopenmpi-dev openmpi-bin)  # MPI is optional for a build; the tests run bakes on ranks
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  echo "setup: installing ${missing[*]}"
  sudo_cmd=""; [ "$(id -u)" -eq 0 ] || sudo_cmd="sudo"
  $sudo_cmd apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo_cmd apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi
