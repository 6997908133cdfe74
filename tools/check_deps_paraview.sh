#!/bin/sh
# tools/check_deps_paraview.sh: check that `make deps build` works on a Debian 12 machine where
# ParaView is installed (issue 13), in a throw-away debootstrap chroot.
#
#   sudo tools/check_deps_paraview.sh [CHROOT]          (default CHROOT: ../chroot-pv)
#   sudo tools/check_deps_paraview.sh --no-paraview [CHROOT]   the same on a bare system
#
# Needs root, debootstrap (apt-get install debootstrap) and Debian's mirror; about 2.5 GB in
# CHROOT and 10-30 minutes the first time (ParaView and its dependencies are ~450 MB to fetch),
# minutes when CHROOT is already there. Not run by `make test`; tests/test_deps.sh (ctest
# deps.select) checks the package choice without network.
#
# Steps, each printed with "==>":
#   1. debootstrap bookworm into CHROOT unless it is there; install `paraview` the way an
#      analyst does (with its Recommends, so python3-paraview too).
#   2. apt-get -s (simulation): the old package list (libvtk9-dev) cannot be installed next to
#      ParaView (python3-vtk9 vs python3-paraview), the list tools/deps.sh chooses can.
#   3. Copy the working tree (tracked and untracked, not ignored; the test data is in data/) to
#      CHROOT/src/terrapatch; there run
#      `make deps build` and `ctest -R '^(export|deps)\.'`.
# Exit 0 when every step succeeds. /proc, /dev and /dev/pts are bind-mounted into CHROOT
# while it runs and unmounted on exit; remove CHROOT by hand when done (rm -rf, not mounted).
set -eu

with_paraview=1
if [ "${1:-}" = --no-paraview ]; then with_paraview=0; shift; fi
case "${1:-}" in -h | --help) sed -n '2,/^set -eu/p' "$0" | sed -e '$d' -e 's/^# \{0,1\}//'; exit 0 ;; esac

repo=$(cd "$(dirname "$0")/.." && pwd)
root=${1:-$(dirname "$repo")/chroot-pv}
mirror=${TP_DEBIAN_MIRROR:-http://deb.debian.org/debian}

[ "$(id -u)" = 0 ] || { echo "check_deps_paraview.sh: needs root (debootstrap, chroot)" >&2; exit 2; }
command -v debootstrap >/dev/null || {
    echo "check_deps_paraview.sh: needs debootstrap (apt-get install debootstrap)" >&2; exit 2; }

say() { printf '==> %s\n' "$*"; }
in_root() { chroot "$root" env DEBIAN_FRONTEND=noninteractive LC_ALL=C.UTF-8 sh -c "$1"; }

mounted=
cleanup() {
    for m in $mounted; do umount "$root/$m" 2>/dev/null || umount -l "$root/$m" || true; done
}
trap cleanup EXIT INT TERM

# 1. The chroot, with ParaView.
if [ ! -x "$root/usr/bin/apt-get" ]; then
    say "debootstrap bookworm into $root"
    debootstrap --variant=minbase bookworm "$root" "$mirror"
fi
cat > "$root/etc/apt/sources.list" <<EOF
deb $mirror bookworm main
deb $mirror bookworm-updates main
deb ${TP_DEBIAN_SECURITY_MIRROR:-http://deb.debian.org/debian-security} bookworm-security main
EOF
cp /etc/resolv.conf "$root/etc/resolv.conf"
printf '#!/bin/sh\nexit 101\n' > "$root/usr/sbin/policy-rc.d" # start no services
chmod +x "$root/usr/sbin/policy-rc.d"
for m in proc dev dev/pts; do
    if ! mountpoint -q "$root/$m"; then
        if [ "$m" = proc ]; then mount -t proc proc "$root/proc"; else mount --bind "/$m" "$root/$m"; fi
        mounted="$m $mounted"
    fi
done
say "apt-get update; install make (minbase has none)"
in_root 'apt-get update -qq && apt-get install -y -q --no-install-recommends make >/dev/null'
if [ "$with_paraview" = 1 ]; then
    say "install paraview (with Recommends: python3-paraview)"
    in_root 'apt-get install -y -q paraview >/dev/null'
    in_root "dpkg-query -W -f='\${Package} \${Version} \${db:Status-Abbrev}\n' paraview python3-paraview"
fi

# 2. Simulations.
rm -rf "$root/src/terrapatch"
mkdir -p "$root/src/terrapatch"
(cd "$repo" && git -c safe.directory="$repo" ls-files -z --cached --others --exclude-standard |
    xargs -0 sh -c 'for f; do [ -e "$f" ] && printf "%s\0" "$f"; done' sh |
    tar --null -T - -cf -) | tar -xf - -C "$root/src/terrapatch"
new=$(in_root 'sh /src/terrapatch/tools/deps.sh --dry-run' | sed -n 's/^packages: //p')
say "tools/deps.sh chooses: $(in_root 'sh /src/terrapatch/tools/deps.sh --dry-run' | sed -n 's/^vtk: //p') VTK"
if [ "$with_paraview" = 1 ]; then
    say "simulate the old list (libvtk9-dev): must fail next to ParaView"
    if in_root 'apt-get -s install --no-install-recommends libvtk9-dev' > "$root/tmp/old.log" 2>&1; then
        cat "$root/tmp/old.log"
        echo "check_deps_paraview.sh: libvtk9-dev installs next to ParaView; the issue is gone?" >&2
        exit 1
    fi
    grep -E 'Depends|Conflicts|Breaks|^E:' "$root/tmp/old.log" || true
fi
say "simulate the new list: must succeed"
in_root "apt-get -s install --no-install-recommends $new" > "$root/tmp/new.log" 2>&1 || {
    cat "$root/tmp/new.log"; exit 1; }
grep -E 'newly installed' "$root/tmp/new.log" || true

# 3. The real thing.
say "make deps build (in $root/src/terrapatch)"
in_root 'cd /src/terrapatch && rm -rf build && make deps build'
grep -E '^VTK_DIR' "$root/src/terrapatch/build/CMakeCache.txt"
say "ctest -R '^(export|deps)\\.'"
in_root "cd /src/terrapatch && ctest --test-dir build --output-on-failure -R '^(export|deps)\\.'"
if [ "$with_paraview" = 1 ]; then
    in_root "dpkg-query -W -f='\${Package} \${db:Status-Abbrev}\n' paraview python3-paraview \
        libvtk9-dev python3-vtk9 2>/dev/null || true"
fi
say "OK: make deps build and the export tests pass$([ "$with_paraview" = 1 ] && echo ' next to ParaView')"
