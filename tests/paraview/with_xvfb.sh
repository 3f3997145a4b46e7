#!/bin/sh
# Runs a command under a private Xvfb server (ParaView's pvbatch renders only through X).
# Xvfb picks a free display number itself and writes it to a pipe once it accepts
# connections (-displayfd), so there is no window in which another server can take the
# number or the command can start before its server is ready. xvfb-run -a chooses the number
# by looking at lock files and, when that display turns out to be taken, can start its
# command on the next one before that server is ready ("bad X server connection").
set -eu
dir="$(mktemp -d)"
pid=""
clean_up() {
    if [ -n "${pid}" ]; then
        kill "${pid}" 2>/dev/null || true
        wait "${pid}" 2>/dev/null || true
    fi
    rm -rf "${dir}"
}
trap clean_up EXIT
# A run stopped by HUP, INT (Ctrl-C) or TERM ends through the EXIT trap too: sh runs that
# trap on `exit`, not when a signal kills it. A KILL (ctest's timeout) leaves the folder.
trap 'exit 129' HUP
trap 'exit 130' INT
trap 'exit 143' TERM
mkfifo "${dir}/display"
# SG_XVFB: the server CMake found (tests/CMakeLists.txt); Xvfb on the PATH otherwise.
# -noreset keeps one server state for the whole run (by default the server resets whenever
# its last client disconnects), a precaution: no reset was shown to cause the rare "bad X server
# connection" failures of this test.
"${SG_XVFB:-Xvfb}" -displayfd 3 -nolisten tcp -noreset -screen 0 1280x1024x24 \
    3>"${dir}/display" 2>"${dir}/xvfb.log" &
pid=$!
number=""
read -r number <"${dir}/display" || true
if [ -z "${number}" ]; then
    echo "with_xvfb.sh: Xvfb did not start: $(tail -n 3 "${dir}/xvfb.log")" >&2
    exit 1
fi
status=0
DISPLAY=":${number}" "$@" || status=$?
if [ "${status}" -ne 0 ]; then
    # What a failed run needs to be told apart from a server that went away.
    state="exited"
    kill -0 "${pid}" 2>/dev/null && state="still answers kill -0"
    echo "with_xvfb.sh: the command failed (status ${status}) on display :${number};" \
        "Xvfb (pid ${pid}) ${state}; its log: $(tail -n 5 "${dir}/xvfb.log" | tr '\n' ' ')" >&2
fi
exit "${status}"
