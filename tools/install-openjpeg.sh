#!/bin/sh
# glymur loads the OpenJPEG shared library (libopenjp2) at run time; install it
# from Debian's packages when it is missing.
set -e
if ldconfig -p 2>/dev/null | grep -q 'libopenjp2\.so'; then
    exit 0
fi
if [ "$(id -u)" = "0" ]; then
    apt-get update -qq
    DEBIAN_FRONTEND=noninteractive apt-get install -y -qq libopenjp2-7 >/dev/null
elif command -v sudo >/dev/null 2>&1; then
    sudo apt-get update -qq
    sudo DEBIAN_FRONTEND=noninteractive apt-get install -y -qq libopenjp2-7 >/dev/null
else
    echo "pdsgen: the OpenJPEG library (libopenjp2) is missing; install the" \
         "Debian package libopenjp2-7 as root" >&2
    exit 1
fi
