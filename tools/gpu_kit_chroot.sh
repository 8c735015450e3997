#!/bin/bash
# tools/gpu_kit_chroot.sh: runs the GPU kit's check as a bare GPU machine would,
# in a chroot that has none of the build packages and no Vulkan loader, with
# this machine's lavapipe standing in for the GPU's driver (tools/README.md
# "GPU kit"). Needs root (chroot, mount).
#
#   tools/gpu_kit_chroot.sh ROOTFS OUTDIR [gpu_check.sh options]
#
#   ROOTFS  a minimal Debian made once, e.g. `debootstrap --variant=minbase bookworm ROOTFS` (Debian: debootstrap)
#   OUTDIR  where the check's files are copied back (check.json, check.log, images.tar, devices.txt)
#
# Copies gpu-kit/ to ROOTFS/kit and lavapipe (libvulkan_lvp.so and every library it needs but glibc's) to
# ROOTFS/opt/lavapipe, as the GPU's driver is installed there (its folder in ld.so.conf, its ICD JSON named by
# VK_DRIVER_FILES); checks that the kit's binaries find every library in the kit and that the chroot has no
# Vulkan loader of its own; then runs /kit/gpu_check.sh /out --allow-cpu with /proc mounted. Exit status: the
# check's; 2 for bad arguments.
set -euo pipefail

ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
fail() { echo "gpu_kit_chroot.sh: $1" >&2; exit "${2:-1}"; }
[[ $# -ge 2 ]] || fail "usage: gpu_kit_chroot.sh ROOTFS OUTDIR [gpu_check.sh options]" 2
ROOTFS=$(realpath "$1")
OUTDIR=$(realpath -m "$2")
shift 2
[[ -x $ROOTFS/bin/bash ]] || fail "$ROOTFS is not a root file system (debootstrap --variant=minbase bookworm $ROOTFS)" 2
[[ -f $ROOT/gpu-kit/KIT.json ]] || fail "no kit: run tools/gpu_kit.sh first" 2
if ls "$ROOTFS"/usr/lib/x86_64-linux-gnu/libvulkan.so* >/dev/null 2>&1; then
    fail "$ROOTFS has a Vulkan loader: the test needs a system without one"
fi

# The stand-in driver: lavapipe and its libraries, glibc's apart.
lvp=$(ldconfig -p | awk '$1 == "libvulkan_lvp.so" {print $NF; exit}')
[[ -n $lvp ]] || fail "lavapipe (libvulkan_lvp.so) is not installed here"
rm -rf "$ROOTFS/kit" "$ROOTFS/out" "$ROOTFS/opt/lavapipe"
mkdir -p "$ROOTFS/opt/lavapipe/lib" "$ROOTFS/out"
cp -L "$lvp" "$ROOTFS/opt/lavapipe/lib/"
ldd "$lvp" | awk '$2 == "=>" && $3 ~ /^\// {print $1, $3}' | while read -r name path; do
    [[ $name =~ ^(libc|libm|libdl|libpthread|librt)\.so ]] || cp -L "$path" "$ROOTFS/opt/lavapipe/lib/$name"
done
cat > "$ROOTFS/opt/lavapipe/icd.json" <<'EOF'
{"file_format_version": "1.0.0", "ICD": {"library_path": "/opt/lavapipe/lib/libvulkan_lvp.so", "api_version": "1.4.305"}}
EOF
rm -f "$ROOTFS/etc/ld.so.conf.d/lavapipe.conf"
cp -r "$ROOT/gpu-kit" "$ROOTFS/kit"
# The driver's libraries are not registered yet: every library of the kit's binaries must come from the kit.
chroot "$ROOTFS" /sbin/ldconfig
unresolved=$(chroot "$ROOTFS" /usr/bin/env LD_LIBRARY_PATH=/kit/lib:/kit/lib/cxx /usr/bin/ldd /kit/bin/whitted \
             /kit/bin/whitted_image_io.so /kit/bin/whitted_kit | awk '$2 == "=>" && $3 !~ /^\/kit\// {print $1}' |
             grep -Ev '^(libc|libm|libdl|libpthread|librt)\.so' || true)
[[ -z $unresolved ]] || fail "libraries the kit's binaries find outside the kit: $unresolved"
echo /opt/lavapipe/lib > "$ROOTFS/etc/ld.so.conf.d/lavapipe.conf"
chroot "$ROOTFS" /sbin/ldconfig

mount -t proc proc "$ROOTFS/proc"
trap 'umount "$ROOTFS/proc"' EXIT
status=0
chroot "$ROOTFS" /usr/bin/env -i PATH=/usr/sbin:/usr/bin:/sbin:/bin HOME=/root TMPDIR=/tmp \
    VK_DRIVER_FILES=/opt/lavapipe/icd.json /bin/bash /kit/gpu_check.sh /out --allow-cpu "$@" || status=$?
mkdir -p "$OUTDIR"
cp -r "$ROOTFS"/out/. "$OUTDIR/"
echo "gpu_kit_chroot.sh: the check exited with $status; its files are in $OUTDIR"
exit $status
