#!/usr/bin/env bash
# Fetches the extra Vulkan implementations the tests run on, each into a private folder
# with an ICD manifest of its own; nothing is installed system-wide.
#
#   third_party/fetch-drivers.sh [DIR]     (default: $LAVA_DRIVERS_DIR or ~/.cache/lava/drivers)
#
#   DIR/lavapipe-25.json   Mesa lavapipe 25.0, mesa-vulkan-drivers from bookworm-backports
#   DIR/swiftshader.json   Google SwiftShader, libvk_swiftshader.so from chromium-common
#
# apt-get download fetches the packages from the mirror the system's own sources name,
# with a private sources list, state and cache under DIR/apt; dpkg -x unpacks them.
# A folder that already holds both manifests is left as it is (delete it to refetch).
set -euo pipefail

dir="${1:-${LAVA_DRIVERS_DIR:-$HOME/.cache/lava/drivers}}"
[ -f "$dir/lavapipe-25.json" ] && [ -f "$dir/swiftshader.json" ] && exit 0

# The Debian mirror of the system's sources (deb822 or one-line format), else Debian's own.
mirror="$(
  { grep -hs '^URIs:' /etc/apt/sources.list.d/*.sources | awk '{print $2}'
    grep -hs '^deb ' /etc/apt/sources.list /etc/apt/sources.list.d/*.list |
      sed -E 's/^deb +(\[[^]]*\] +)?//' | awk '{print $1}'
  } | grep -v -- '-security' | grep -m1 '/debian/\?$' || true)"
mirror="${mirror:-http://deb.debian.org/debian}"
mirror="${mirror%/}"
security="${mirror%/debian}/debian-security"

echo "third_party: fetching lavapipe 25 and SwiftShader into $dir"
apt="$dir/apt"
rm -rf "$apt" "$dir/lavapipe-25" "$dir/swiftshader" "$dir/versions.txt"
mkdir -p "$apt/lists/partial" "$apt/cache/archives/partial" "$apt/etc" "$dir/debs"
keyring="[signed-by=/usr/share/keyrings/debian-archive-keyring.gpg]"
cat > "$apt/etc/sources.list" <<EOF
deb $keyring $mirror bookworm main
deb $keyring $mirror bookworm-updates main
deb $keyring $mirror bookworm-backports main
deb $keyring $security bookworm-security main
EOF
options=(-o "Dir::Etc::sourcelist=$apt/etc/sources.list" -o Dir::Etc::sourceparts=/dev/null
         -o "Dir::State::Lists=$apt/lists" -o "Dir::Cache=$apt/cache" -o Debug::NoLocking=1 -qq)
# As root, apt would hand the download to its _apt user, who cannot write the folder.
[ "$(id -u)" -ne 0 ] || options+=(-o APT::Sandbox::User=root)
apt-get "${options[@]}" update
rm -f "$dir"/debs/*.deb
(cd "$dir/debs" && apt-get "${options[@]}" download chromium-common \
                   mesa-vulkan-drivers/bookworm-backports)

# Only the drivers are kept (chromium-common is mostly not SwiftShader), and their versions.
unpacked="$dir/unpacked"
mkdir -p "$dir/lavapipe-25" "$dir/swiftshader"
for deb in "$dir"/debs/*.deb; do
  dpkg -x "$deb" "$unpacked"
  dpkg-deb -f "$deb" Package Version | sed 's/^[^:]*: //' | paste -sd' ' >> "$dir/versions.txt"
done
mv "$unpacked/usr/lib/x86_64-linux-gnu/libvulkan_lvp.so" "$dir/lavapipe-25/"
mv "$unpacked/usr/lib/chromium/libvk_swiftshader.so" "$dir/swiftshader/"
rm -rf "$apt" "$dir/debs" "$unpacked"

# The packages' manifests name the libraries relative to where a system install puts them.
printf '{"file_format_version": "1.0.0", "ICD": {"library_path": "%s", "api_version": "1.4.305"}}\n' \
  "$dir/lavapipe-25/libvulkan_lvp.so" > "$dir/lavapipe-25.json"
printf '{"file_format_version": "1.0.0", "ICD": {"library_path": "%s", "api_version": "1.3.0"}}\n' \
  "$dir/swiftshader/libvk_swiftshader.so" > "$dir/swiftshader.json"
