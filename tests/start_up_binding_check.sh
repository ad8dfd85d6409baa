#!/bin/sh
# The patchsim program binds nothing of OpenImageIO at start-up (it is a module loaded on first
# use) and has no thread_local with a destructor: registering one waits for a dlopen under way,
# which would stall a worker for the image module's whole load (backend/images/image_io_module.h).
# Usage: start_up_binding_check.sh PATH_TO_PATCHSIM
set -eu
program=$1
command -v readelf >/dev/null && command -v nm >/dev/null || { echo "needs readelf and nm"; exit 1; }
needed=$(readelf -d "$program" | grep NEEDED)
[ -n "$needed" ] || { echo "readelf found no NEEDED entries in $program"; exit 1; }
if echo "$needed" | grep -q OpenImageIO; then
    echo "$program links OpenImageIO directly:"; echo "$needed" | grep OpenImageIO; exit 1
fi
if nm -D --undefined-only "$program" | grep -q __cxa_thread_atexit; then
    echo "$program has a thread_local with a destructor (__cxa_thread_atexit)"; exit 1
fi
echo "no OpenImageIO among $(echo "$needed" | wc -l) libraries bound at start-up; no thread_local with a destructor"
