# window_lib.sh - what the window_*.sh tests share: a private X server (Xvfb) on a free display
# number, the viewer started in it and its window found with its frame loop running, and the
# viewer closed with Esc. Sourced (not run) after setting name (for messages), exe and dir:
#   . "$(dirname "$0")/window_lib.sh"
#   window_xvfb FIRST LAST  Xvfb on the first free display in FIRST..LAST, DISPLAY exported,
#                           both processes ended at exit. Needs Xvfb and xdotool (`make deps`
#                           installs them); exits 1 without them: a skip would hide that the
#                           window was never tried.
#   window_view ARGS...     `$exe view --size 960x540 ARGS...` (stdout, stderr in $dir/stdout.txt,
#                           stderr.txt); sets vpid and wid once the title shows a frame rate;
#                           exits 1 when no window appears.
#   window_focus            focuses the window and waits a second.
#   window_close            Esc, then up to 10 s for the viewer to end (then it is killed);
#                           sets rc (its exit status) and escaped (1 when Esc closed it).

window_xvfb() {
    local tool n
    for tool in Xvfb xdotool; do
        command -v "$tool" >/dev/null || { echo "$name: $tool is missing (make deps installs it)"; exit 1; }
    done
    display=
    for n in $(seq "$1" "$2"); do
        if [ ! -e "/tmp/.X$n-lock" ] && [ ! -e "/tmp/.X11-unix/X$n" ]; then display=$n; break; fi
    done
    [ -n "$display" ] || { echo "$name: no free X display number"; exit 1; }
    Xvfb ":$display" -screen 0 1280x800x24 -nolisten tcp >"$dir/xvfb.log" 2>&1 &
    xpid=$!
    vpid=
    trap window_cleanup EXIT
    export DISPLAY=":$display"
    for _ in $(seq 50); do xdotool getdisplaygeometry >/dev/null 2>&1 && break; sleep 0.1; done
}

window_cleanup() {
    [ -n "$vpid" ] && kill "$vpid" 2>/dev/null
    kill "$xpid" 2>/dev/null
    wait 2>/dev/null
}

window_view() {
    "$exe" view --size 960x540 "$@" >"$dir/stdout.txt" 2>"$dir/stderr.txt" &
    vpid=$!
    wid=
    for _ in $(seq 300); do
        wid=$(xdotool search --name '^terrapatch' 2>/dev/null | head -n1)
        [ -n "$wid" ] && break
        kill -0 "$vpid" 2>/dev/null || break
        sleep 0.1
    done
    if [ -z "$wid" ]; then
        echo "$name: no terrapatch window appeared"; cat "$dir/stderr.txt"; exit 1
    fi
    # the frame loop runs once the title shows a frame rate
    for _ in $(seq 300); do
        xdotool getwindowname "$wid" 2>/dev/null | grep -q fps && break
        sleep 0.1
    done
}

window_focus() {
    xdotool windowfocus --sync "$wid" 2>/dev/null || true
    sleep 1
}

window_close() {
    xdotool key Escape
    for _ in $(seq 100); do kill -0 "$vpid" 2>/dev/null || break; sleep 0.1; done
    escaped=1
    if kill -0 "$vpid" 2>/dev/null; then
        escaped=0
        kill "$vpid"
    fi
    wait "$vpid"
    rc=$?
    vpid=
}
