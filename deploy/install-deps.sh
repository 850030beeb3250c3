#!/usr/bin/env bash
# Installs every Debian 12 package sweepd needs to build, test and run; idempotent.
# Runs `apt-get update` once, and only when something is missing. Works as root or via sudo.
# Where npm is present, also installs into .tools/ (used by tests): the Khronos glTF validator,
# kubernetes-models + yaml (the offline schema check of deploy/k8s/), osc (a VMC sender), and
# into .tools/web/ the browser viewer's packages exactly as client_examples/web/package-lock.json
# pins them.
# A clone finds them in ~/.cache/sweepd/ when this machine installed the same ones before.
set -euo pipefail

packages=(
  cmake ninja-build g++ pkg-config make
  ccache  # the presets' compiler launcher (CMakePresets.json): a fresh clone reuses the objects any clone on this machine built
  libglm-dev libtinygltf-dev libopenmesh-dev libopenexr-dev libasio-dev
  libegl-dev libopengl-dev libegl-mesa0 libgl1-mesa-dri mesa-utils-bin
  nlohmann-json3-dev libstb-dev libgtest-dev libgmock-dev libbenchmark-dev
  flatbuffers-compiler libflatbuffers-dev python3 python3-flatbuffers zlib1g-dev libcli11-dev
  libdeflate-dev  # deflate of ZIP position maps (io/exr/exr_zip_encode.h): 0.52-0.63x zlib's time
  libmeshoptimizer-dev  # the protocol's Meshopt position format (protocol/meshopt_vertices.h); Python's sweepd-client loads its libmeshoptimizer.so.2d
  strace  # tests/server/daemon_upload_confinement_test.cpp traces the daemon's file calls
  libssl-dev openssl  # TLS in sweepd and its clients (Asio's ssl over OpenSSL); the TLS tests make certificates with openssl
  curl prometheus  # tests/server/daemon_http_side_port_test.cpp: curl, promtool, a real scrape
  libwebsocketpp-dev  # sweepd's WebSocket listener (--ws-listen, server/transport/websocket_session.h); header-only
  libsystemd-dev  # sd_notify for the Type=notify unit (server/systemd_notifier.h)
  liblo-dev liblo-tools  # the VMC receiver's OSC messages (server/services/vmc/osc_packet.h, found by pkg-config); oscsend in tests/server/daemon_vmc_test.cpp
  python3-numpy python3-venv python3-setuptools python3-pip  # client_examples/python (sweepd-client), pip-installed offline in tests/server/python_package_test.cpp
  ffmpeg  # sweepctl sheet --video pipes its frames to ffmpeg (cli/video_encoder.h)
  libassimp-dev  # FBX and COLLADA models (io/assimp/assimp_load.h): sweepctl MODEL files, tests/io/assimp/assimp_load_test
  assimp-utils  # the `assimp` command (assimp export in.glb out.fbx): FBX by hand, as the tests make it
  haproxy  # deploy/haproxy.cfg: checked with haproxy -c and run in front of two daemons (tests/deploy/)
  clang libclang-rt-14-dev  # make sanitize, make tsan and make fuzz compile with Clang 14 and its sanitizer runtimes (CMakePresets.json)
  chromium  # headless, on SwiftShader: tests/server/browser_viewer_test.cpp and bench/viewer_bench.sh load the viewer
  blender  # headless (3.4): tests/cli/blender_point_cache_test.cpp plays sweepctl's PC2 and MDD caches in its Mesh Cache modifier
  mkdocs mkdocs-material python3-pymdownx  # make docs: the site in docs/ (mkdocs.yml); tests/docs/docs_site_test.py builds it --strict
)

# One dpkg-query for all (one per package took 2-10 s on a loaded machine, in every make).
installed=$(dpkg-query -W -f='${Package} ${Status}\n' "${packages[@]}" 2>/dev/null \
  | awk '/ install ok installed$/ {print $1}' || true)
missing=()
for p in "${packages[@]}"; do
  grep -qxF "$p" <<<"$installed" || missing+=("$p")
done

if ((${#missing[@]})); then
  sudo_cmd=()
  if [ "$(id -u)" -ne 0 ]; then
    command -v sudo >/dev/null || { echo "install-deps: need root or sudo to install: ${missing[*]}" >&2; exit 1; }
    sudo_cmd=(sudo)
  fi
  echo "install-deps: installing ${missing[*]}"
  "${sudo_cmd[@]}" apt-get update -qq
  DEBIAN_FRONTEND=noninteractive "${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}"
else
  echo "install-deps: all ${#packages[@]} Debian packages present"
fi

root=$(cd "$(dirname "$0")/.." && pwd)
modules="$root/.tools/node_modules"
# npm packages the tests use: "directory under node_modules|package@version ...|what skips without".
npm_tools=(
  "gltf-validator|gltf-validator@2.0.0-dev.3.10|the glTF validator tests"
  "kubernetes-models|kubernetes-models@4.5.1 yaml@2.9.1|the Kubernetes schema check of deploy/k8s/"
  "osc|osc@2.4.5|the VMC test's sender on npm osc (tests/tools/vmc_osc_send.js)"
)
# A clone on a machine that installed the same npm packages before takes them from the user's cache
# (hard links: npm replaces the packages' files, and its own two are copied before it runs), as
# ccache serves compiled objects; a fresh clone's make test saves the ~20 s of npm. Keyed by the
# packages and the viewer's lock file.
tools_key=$(printf '%s\n' "${npm_tools[@]}" | cat - "$root/client_examples/web/package-lock.json" \
  | sha256sum | cut -c1-16)
tools_cache="${XDG_CACHE_HOME:-$HOME/.cache}/sweepd/npm-tools-$tools_key"
if [ ! -e "$root/.tools" ] && [ -f "$tools_cache/complete" ]; then
  cp -al "$tools_cache/tools" "$root/.tools" 2>/dev/null || cp -a "$tools_cache/tools" "$root/.tools"
  echo "install-deps: npm packages from $tools_cache"
fi
if command -v npm >/dev/null; then
  for tool in "${npm_tools[@]}"; do
    IFS='|' read -r directory specs skips <<<"$tool"
    if [ ! -d "$modules/$directory" ]; then
      echo "install-deps: installing $specs (npm) into .tools/"
      # npm rewrites these two in place: this clone's own copies, so that the cache they are
      # hard links into (below) stays as it was.
      for file in package.json package-lock.json; do
        if [ -f "$root/.tools/$file" ]; then
          cp "$root/.tools/$file" "$root/.tools/$file.own" && mv "$root/.tools/$file.own" "$root/.tools/$file"
        fi
      done
      # shellcheck disable=SC2086  # specs is a list of package@version
      npm install --silent --no-audit --no-fund --prefix "$root/.tools" $specs >/dev/null \
        || echo "install-deps: warning: $specs could not be installed; $skips will skip" >&2
    fi
  done
  # The viewer's three.js, flatbuffers, meshoptimizer and esbuild (client_examples/web): `npm ci` from the
  # committed lock file, again whenever the lock file changes.
  web="$root/.tools/web"
  if ! cmp -s "$root/client_examples/web/package-lock.json" "$web/package-lock.json"; then
    echo "install-deps: installing the viewer's npm packages into .tools/web/"
    mkdir -p "$web"
    cp "$root/client_examples/web/package.json" "$root/client_examples/web/package-lock.json" "$web/"
    # In the directory itself: npm ci --prefix mistakes a .tools that is a symlink for a link.
    (cd "$web" && npm ci --silent --no-audit --no-fund >/dev/null) || {
      rm -f "$web/package-lock.json"  # tried again on the next run
      echo "install-deps: warning: the viewer's npm packages could not be installed; the browser viewer is not built" >&2
    }
  fi
  # Into the cache once everything above is in place (a partial install is never cached).
  complete=true
  for tool in "${npm_tools[@]}"; do
    [ -d "$modules/${tool%%|*}" ] || complete=false
  done
  cmp -s "$root/client_examples/web/package-lock.json" "$web/package-lock.json" || complete=false
  if $complete && [ ! -f "$tools_cache/complete" ]; then
    rm -rf "$tools_cache" && mkdir -p "$tools_cache"
    { cp -al "$root/.tools" "$tools_cache/tools" 2>/dev/null || cp -a "$root/.tools" "$tools_cache/tools"; } \
      && touch "$tools_cache/complete"
  fi
else
  echo "install-deps: npm not found; the glTF validator tests, the Kubernetes schema check and the browser viewer will skip"
fi
