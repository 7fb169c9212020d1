#!/usr/bin/env bash
# Installs the Debian 12 packages raplas needs, only those that are missing.
set -euo pipefail
pkgs=(build-essential cmake ninja-build pkg-config git
      libsystemc-dev libtinyobjloader-dev libopenimageio-dev libgtest-dev libembree-dev
      libcli11-dev nlohmann-json3-dev libtomlplusplus-dev libcsv-dev libxxhash-dev
      python3 python3-matplotlib clang libclang-rt-14-dev parallel verilator)
missing=()
for p in "${pkgs[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  echo "installing: ${missing[*]}"
  SUDO=""
  [ "$(id -u)" -eq 0 ] || SUDO="sudo"
  export DEBIAN_FRONTEND=noninteractive
  $SUDO apt-get update -qq
  $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi
