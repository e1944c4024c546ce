"""Ctrl-C ends a long run or step cleanly: KeyboardInterrupt, and the recording is closed."""
import os
import signal
import subprocess
import sys
import textwrap
import time

import tactus

SCRIPT = textwrap.dedent("""
    import sys
    import tactus
    record, mode = sys.argv[1], sys.argv[2]
    model = tactus.default_scene()
    if mode == "run":
        tactus.run(model, 0.01)  # compiled once, so the long run below starts at once
        print("started", flush=True)
        try:
            tactus.run(model, duration=3600.0, max_duration=3600.0, record=record)
        except KeyboardInterrupt as e:
            print("interrupted:", e, flush=True)
    else:
        sim = tactus.Simulation(model, record=record)
        print("started", flush=True)
        try:
            sim.step(10**9)
        except KeyboardInterrupt:
            sim.step(10)  # it goes on after the interrupt
            print("interrupted: frame", sim.frame, flush=True)
            sim.finish()
""")


def interrupt(mode, tmp_path):
    record = tmp_path / f"{mode}.tacrec"
    script = tmp_path / "long_run.py"
    script.write_text(SCRIPT)
    p = subprocess.Popen([sys.executable, script, record, mode], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                         text=True, env=os.environ.copy())
    assert p.stdout.readline().strip() == "started"
    time.sleep(1.0)  # well inside the hour-long run
    p.send_signal(signal.SIGINT)
    out, err = p.communicate(timeout=60)
    assert p.returncode == 0, err
    return out, tactus.read_recording(record)


def test_ctrl_c_ends_a_run_cleanly(tmp_path):
    out, rec = interrupt("run", tmp_path)
    assert "interrupted: run interrupted at t = " in out, out
    stopped_at = float(out.split("t = ")[1].split(" s")[0])
    assert 0.0 < stopped_at < 3600.0
    assert rec["complete"], rec["truncation"]
    assert rec["frames"]["t"].max() <= stopped_at + 1e-9


def test_ctrl_c_stops_step_after_its_slice_and_the_simulation_goes_on(tmp_path):
    out, rec = interrupt("step", tmp_path)
    assert out.startswith("interrupted: frame "), out
    frames = int(out.split()[-1])
    assert frames > 10 and frames % 1000 == 10  # whole slices of 1,000 periods, then 10 more
    assert rec["complete"], rec["truncation"]
    assert len(set(rec["frames"]["frame"].tolist())) == frames
