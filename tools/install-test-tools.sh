#!/bin/sh
# The tools the test suite compares pdsgen with, from Debian's packages, installed
# when missing: GDAL's command-line tools (gdalinfo, ogrinfo, gdal_translate), its
# Python scripts (gdal_merge.py, gdalbuildvrt's companions) and headless Chromium
# (review pages are rendered in a real browser).
set -e
need=""
command -v gdalinfo >/dev/null 2>&1 || need="$need gdal-bin"
command -v gdal_merge.py >/dev/null 2>&1 || need="$need python3-gdal"
command -v chromium >/dev/null 2>&1 || need="$need chromium"
[ -z "$need" ] && exit 0
run() {
    if [ "$(id -u)" = "0" ]; then "$@"
    elif command -v sudo >/dev/null 2>&1; then sudo "$@"
    else
        echo "pdsgen: the test tools ($need ) are missing; install these Debian packages as root" >&2
        exit 1
    fi
}
run apt-get update -qq
run env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends $need >/dev/null
