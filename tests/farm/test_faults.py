# Faults: a worker process killed mid-render (Dask reruns its tasks; the image is still
# bit-identical), a bad scene (one clear error naming the file and JSON path, no processes left),
# an unreachable scheduler (a clear error within the timeout), Ctrl-C (the whole job cancelled,
# no processes left).
import os
import signal
import subprocess
import threading
import time

import pytest

import facet.farm as farm
from conftest import assert_same, cli_render, farm_cmd, session_processes, write_scene


def wait_gone(sid, seconds):
    deadline = time.monotonic() + seconds
    while time.monotonic() < deadline:
        left = session_processes(sid)
        if not left:
            return []
        time.sleep(0.1)
    return session_processes(sid)


def test_killed_worker_task_is_rerun_bit_identical(tmp_path):
    scene = write_scene(tmp_path / "s.json", 256, 192, 16, seed=5)
    ref = cli_render(scene, tmp_path / "ref.exr")
    cluster = farm.local_cluster(2, 1)
    client = farm.connect(cluster)
    try:
        client.wait_for_workers(2, timeout=60)
        payload = farm.load_payload(str(scene))
        regions, samples = farm.plan_still(256, 192, 16, 2, tile_size=32, sample_chunk=8)
        job = farm.Job(payload, regions, samples, [str(tmp_path / "o.exr")])
        killed = {}

        def kill_a_busy_worker(part):
            if killed:
                return
            pids = client.run(os.getpid)
            busy = [a for a, keys in client.processing().items() if keys and a in pids]
            assert busy, "no worker was running a task"
            killed["pid"] = pids[busy[0]]
            killed["tasks"] = len(client.processing()[busy[0]])
            os.kill(killed["pid"], signal.SIGKILL)

        [image] = farm.run_jobs(client, [job], on_result=kill_a_busy_worker)
        assert killed["tasks"] >= 1
        with pytest.raises(ProcessLookupError):
            os.kill(killed["pid"], 0)
        assert_same(image, ref)
    finally:
        client.close()
        cluster.close()


def run_farm(args, timeout=60):
    p = subprocess.Popen(farm_cmd(*args), stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                         text=True, start_new_session=True)
    try:
        out, err = p.communicate(timeout=timeout)
    finally:
        if p.poll() is None:
            os.killpg(p.pid, signal.SIGKILL)
    return p, out, err


@pytest.mark.parametrize("kind", ["unknown_material", "json_syntax", "bad_frame"])
def test_bad_scene_is_one_clear_error(tmp_path, kind):
    good = write_scene(tmp_path / "good_0001.json", 32, 32, 2)
    bad = tmp_path / "bad_0002.json"
    if kind == "json_syntax":
        bad.write_text(good.read_text().replace('"shapes"', '"shapes" 1', 1))
        expect = "column"
    else:
        def edit(d):
            d["shapes"][1]["material"] = "no_such_material"
        write_scene(bad, 32, 32, 2, edit=edit)
        expect = "/shapes/1"
    scenes = [good, bad] if kind == "bad_frame" else [bad]
    out = "o_####.exr" if kind == "bad_frame" else "o.exr"
    t = time.monotonic()
    p, stdout, stderr = run_farm(["render", *scenes, "-o", tmp_path / out])
    assert time.monotonic() - t < 30
    assert p.returncode == 1
    assert "bad_0002.json" in stderr and expect in stderr, stderr
    assert stderr.count("facet-farm: error:") == 1 and stderr.count("\n") == 1, stderr
    assert wait_gone(p.pid, 5) == []
    assert not list(tmp_path.glob("o*.exr"))


def test_unreachable_scheduler_is_a_clear_error_within_the_timeout(tmp_path):
    scene = write_scene(tmp_path / "s.json", 16, 16, 1)
    import socket
    with socket.socket() as s:  # a loopback port nobody listens on
        s.bind(("127.0.0.1", 0))
        port = s.getsockname()[1]
    address = f"tcp://127.0.0.1:{port}"
    t = time.monotonic()
    p, _, stderr = run_farm(["render", scene, "-o", tmp_path / "o.exr", "--scheduler", address,
                             "--timeout", "2"])
    elapsed = time.monotonic() - t
    assert p.returncode == 1
    assert address in stderr and "Traceback" not in stderr, stderr
    assert elapsed < 15, elapsed
    assert wait_gone(p.pid, 5) == []


@pytest.mark.parametrize("workers", [0, 2], ids=["inproc", "2proc"])
def test_ctrl_c_cancels_the_whole_job(tmp_path, workers):
    scene = write_scene(tmp_path / "s.json", 320, 240, 1024)
    p = subprocess.Popen(farm_cmd("render", scene, "-o", tmp_path / "o.exr", "--tile-size", "16",
                                  "--progress", "--workers", workers),
                         stdout=subprocess.PIPE, stderr=subprocess.PIPE, start_new_session=True)
    err = bytearray()
    started = threading.Event()

    def read():
        while True:
            b = os.read(p.stderr.fileno(), 4096)
            if not b:
                return
            err.extend(b)
            if b"tiles" in err:
                started.set()

    reader = threading.Thread(target=read, daemon=True)
    reader.start()
    try:
        assert started.wait(60), err.decode()
        # the client and its worker processes (none: in-process worker threads)
        assert len(session_processes(p.pid)) >= 1 + workers
        t = time.monotonic()
        os.killpg(p.pid, signal.SIGINT)  # what a terminal's Ctrl-C does
        rc = p.wait(timeout=30)
        cancel_s = time.monotonic() - t
        reader.join(5)
        text = err.decode()
        assert rc == 130, text
        assert "cancelled" in text and "Traceback" not in text, text
        assert cancel_s < 15, cancel_s
        assert wait_gone(p.pid, 10) == []
        assert not (tmp_path / "o.exr").exists()
    finally:
        if p.poll() is None:
            os.killpg(p.pid, signal.SIGKILL)
