# Debian packages the build needs; sourced by .ci/run and .ci/demo. ccache lets .ci/run compile
# each source once although three builds compile pce::sim's sources with the same flags (the
# main build, the add_subdirectory consumer test's and the Python package's).
# libopenblas0-serial becomes the system libblas.so.3 that CHOLMOD calls: on the hammock's
# contact matrices a supernodal factorisation takes ~180 ms with it and ~340-500 ms with
# the reference BLAS (the pthread/OpenMP builds are 6-9x slower still on these small
# supernodes, so it is the serial one).
# ffmpeg (with ffprobe) encodes pce-sim's --video movies, run as a child process (nothing
# links it); the tests count a movie's frames with ffprobe.
PCE_DEBIAN_PACKAGES="g++ cmake ninja-build pkg-config libeigen3-dev libboost-dev libgtest-dev libbenchmark-dev nlohmann-json3-dev libfcl-dev libccd-dev libcgal-dev libsuitesparse-dev libcli11-dev libstb-dev libopenblas0-serial libbullet-dev libhypre-dev python3-matplotlib python3-dev python3-venv doxygen clang-format clang-tidy ccache ffmpeg"

pce_install_deps() {
  local sudo=""
  [ "$(id -u)" = 0 ] || sudo="sudo"
  # Skip apt entirely when everything is already there (fast reruns, offline machines).
  if dpkg-query -W -f='${Status}\n' $PCE_DEBIAN_PACKAGES 2>/dev/null | grep -vq "install ok installed" ||
     [ "$(dpkg-query -W -f='${Status}\n' $PCE_DEBIAN_PACKAGES 2>/dev/null | wc -l)" -ne "$(echo $PCE_DEBIAN_PACKAGES | wc -w)" ]; then
    export DEBIAN_FRONTEND=noninteractive
    $sudo apt-get update -qq
    $sudo apt-get install -y -qq --no-install-recommends $PCE_DEBIAN_PACKAGES >/dev/null
  fi
}
