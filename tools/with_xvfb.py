#!/usr/bin/env python3
"""Runs a command on a private Xvfb server, then stops the server.

    with_xvfb.py [--screen WxHxD] -- COMMAND [ARGS...]

Exit status: the command's (2 when Xvfb does not start). Used instead of xvfb-run by the
ParaView plugin's tests and benchmarks (and by bench_vtk.py through `start_xvfb`), because:

- the server picks a free display number itself (-displayfd; its lock file is taken atomically),
  so tests started at the same moment cannot pick the same one, and it reports the number only
  once it accepts connections;
- -noreset: the server does not reset when its last client disconnects. pvbatch probes OpenGL
  with a window of its own and closes that connection before it opens its render window, and
  under mpirun each rank does so: a rank connecting while the server reset after another rank's
  probe was refused ("bad X server connection"), now and then;
- the server is stopped and waited for before this returns, also when this is terminated (a
  test timeout), so no server outlives its test.
"""
import os
import signal
import subprocess
import sys


def start_xvfb(screen="1280x1024x24"):
    """Starts Xvfb on a free display; returns (process, ":N"). Raises RuntimeError when it does not start."""
    rfd, wfd = os.pipe()
    try:
        server = subprocess.Popen(["Xvfb", "-displayfd", str(wfd), "-screen", "0", screen, "-nolisten", "tcp", "-noreset"],
                                  stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
                                  pass_fds=(wfd,))
    except FileNotFoundError:
        os.close(rfd)
        os.close(wfd)
        raise RuntimeError("Xvfb is not installed (apt-get install xvfb)")
    os.close(wfd)
    with os.fdopen(rfd) as f:
        number = f.readline().strip()
    if not number.isdigit():
        server.kill()
        server.wait()
        raise RuntimeError(f"Xvfb did not start (exit status {server.poll()})")
    return server, ":" + number


def stop_xvfb(server):
    """Stops the server and waits for it (its lock file and socket are gone afterwards)."""
    if server.poll() is None:
        server.terminate()
        try:
            server.wait(timeout=20)
        except subprocess.TimeoutExpired:
            server.kill()
            server.wait()


def main(argv):
    screen = "1280x1024x24"
    args = list(argv)
    if args[:1] == ["--screen"] and len(args) >= 2:
        screen = args[1]
        args = args[2:]
    if args[:1] == ["--"]:
        args = args[1:]
    if not args:
        print(__doc__, file=sys.stderr)
        return 2
    try:
        server, display = start_xvfb(screen)
    except RuntimeError as e:
        print(f"with_xvfb.py: {e}", file=sys.stderr)
        return 2
    child = None

    def terminate(signum, _frame):
        if child is not None and child.poll() is None:
            child.send_signal(signum)
            try:
                child.wait(timeout=10)
            except subprocess.TimeoutExpired:
                child.kill()
        stop_xvfb(server)
        sys.exit(128 + signum)

    signal.signal(signal.SIGTERM, terminate)
    signal.signal(signal.SIGINT, terminate)
    try:
        env = dict(os.environ, DISPLAY=display)
        env.pop("XAUTHORITY", None)  # (the server has no access control file: local clients only, -nolisten tcp)
        child = subprocess.Popen(args, env=env)
        return child.wait()
    except FileNotFoundError:
        print(f"with_xvfb.py: no program {args[0]}", file=sys.stderr)
        return 127
    finally:
        stop_xvfb(server)


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
