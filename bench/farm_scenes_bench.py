#!/usr/bin/python3
"""facet-farm on issue 25's big scenes (§4): the forest (bench/forest.py: 10^4 instances of a
10^5-triangle tree) and the textured asset (bench/staged_bench.py: ClearCoatTest.gltf with its
textures under studio.exr). Per-task costs measured on a local Dask cluster of worker processes,
the scaling model built from them, and the model's prediction against the measured wall time
on 1 and 2 workers.

  PYTHONPATH=build/core/python /usr/bin/python3 bench/farm_scenes_bench.py [--reps 3]
      [--forest-spp 32] [--asset-spp 64] [--out /tmp/farm-scenes]

Per scene:
  - client: load_payload (read the JSON and mesh files, build the scene once to validate it);
  - payload: pickled bytes sent through the scheduler (textures are not in it: workers read
    them from the scene's directory), once per worker;
  - worker build: on a worker process, the payload to a Scene (mesh files written, textures and
    HDRI read, BVH built), with the cache emptied first; median of --reps;
  - render: core seconds per sample per pixel, the whole image in one task on one thread on a
    worker whose scene is built (median of --reps);
  - task overhead: a task of 1 pixel x 1 sample on a built scene, round trip (median of 50).
Model for P one-thread workers (P <= cores), all tasks of one plan (farm.plan_still):
  T(P) = client + start(P) + ship + build + (W + n c_task) / P + tail
with W = pixels x spp x render cost, n tasks of c_task overhead each, ship = payload bytes over
loopback (measured as part of the first task: included in build here), tail = half a task (the
last wave's idle slot, on average), start(P) the cluster's start-up (measured per P). Measured:
the wall time of farm.render_files on a fresh LocalCluster(P worker processes x 1 thread),
excluding the cluster's start (reported beside it). Prints markdown.
"""
import argparse
import json
import os
import pathlib
import pickle
import statistics
import sys
import time

ROOT = pathlib.Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "bench"))

import facet  # noqa: E402
import facet.farm as farm  # noqa: E402


def _build_on_worker(payload):
    farm._scenes.clear()
    t = time.perf_counter()
    farm._worker_scene(payload)
    return time.perf_counter() - t


def _render_on_worker(payload, region, samples):
    farm._worker_scene(payload)
    t = time.perf_counter()
    c0 = time.process_time()
    farm.render_piece(payload, region, samples, 1)
    return time.perf_counter() - t, time.process_time() - c0


def write_forest(out, instances, spp):
    import forest

    pos, idx = forest.tree_mesh()
    forest.write_ply(out / "tree.ply", pos, idx)
    path = out / f"forest_{instances}.json"
    path.write_text(json.dumps(forest.scene(instances, False, 320, 240, spp)))
    return path


def write_asset(out, spp):
    import staged_bench

    files = staged_bench.write_scenes(str(out / "staged"))
    d = json.loads(pathlib.Path(files["textured_asset"]).read_text())
    d["render"]["spp"] = spp
    path = pathlib.Path(files["textured_asset"]).with_name(f"textured_asset_{spp}.json")
    path.write_text(json.dumps(d))
    return path


def costs(path, reps):
    t = time.perf_counter()
    payload = farm.load_payload(str(path))
    client_s = time.perf_counter() - t
    sent = len(pickle.dumps(payload, protocol=5))
    cluster = farm.local_cluster(1, 1)
    client = farm.connect(cluster)
    client.wait_for_workers(1)
    try:
        # The payload as run_jobs sends it: once, as a task's result the others depend on.
        data = client.submit(farm._scene_data, payload, pure=False)
        builds = [client.submit(_build_on_worker, data, pure=False).result()
                  for _ in range(reps)]
        full = (0, 0, payload.width, payload.height)
        renders = [client.submit(_render_on_worker, data, full, (0, payload.spp),
                                 pure=False).result() for _ in range(reps)]
        one = [client.submit(_render_on_worker, data, (0, 0, 1, 1), (0, 1),
                             pure=False) for _ in range(3)]  # warm
        client.gather(one)
        overhead = []
        for _ in range(50):
            t = time.perf_counter()
            client.submit(farm.render_piece, data, (0, 0, 1, 1), (0, 1), 1,
                          pure=False).result()
            overhead.append(time.perf_counter() - t)
    finally:
        client.close()
        cluster.close()
    px = payload.width * payload.height
    render_cpu = statistics.median(r[1] for r in renders)
    return dict(payload=payload, client_s=client_s, sent=sent, build_s=statistics.median(builds),
                builds=builds, render_cpu_s=render_cpu,
                render_wall_s=statistics.median(r[0] for r in renders),
                per_sample=render_cpu / (px * payload.spp), task_s=statistics.median(overhead))


def measure(path, workers, reps):
    """Wall time of render_files on a fresh cluster of `workers` processes x 1 thread (start-up
    excluded, reported apart), median of reps; the image checked against the first run's."""
    walls, starts, tasks, images = [], [], 0, []
    for _ in range(reps):
        t = time.perf_counter()
        cluster = farm.local_cluster(workers, 1)
        client = farm.connect(cluster)
        client.wait_for_workers(workers)
        starts.append(time.perf_counter() - t)
        stats = {}
        try:
            t = time.perf_counter()
            [image] = farm.render_files([str(path)], [str(path.with_suffix(f".farm{workers}.exr"))],
                                        client=client, stats=stats)
            walls.append(time.perf_counter() - t)
        finally:
            client.close()
            cluster.close()
        tasks = stats["tasks"]
        images.append(image)
    for im in images[1:]:
        assert (im == images[0]).all(), "farm images differ between runs"
    return dict(wall=statistics.median(walls), walls=walls, start=statistics.median(starts),
                tasks=tasks)


def predict(c, P, tasks):
    p = c["payload"]
    work = p.width * p.height * p.spp * c["per_sample"]
    per_task = work / tasks
    return (c["client_s"] + c["build_s"] + (work + tasks * c["task_s"]) / P + 0.5 * per_task,
            work)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--reps", type=int, default=3)
    ap.add_argument("--instances", type=int, default=10_000)
    ap.add_argument("--forest-spp", type=int, default=32)
    ap.add_argument("--asset-spp", type=int, default=64)
    ap.add_argument("--out", default="/tmp/farm-scenes")
    a = ap.parse_args()
    farm.quiet_logs()
    out = pathlib.Path(a.out)
    out.mkdir(parents=True, exist_ok=True)
    scenes = {f"forest ({a.instances} instances, 320x240, {a.forest_spp} spp)":
              write_forest(out, a.instances, a.forest_spp),
              f"textured_asset (192x128, {a.asset_spp} spp)": write_asset(out, a.asset_spp)}
    print("## Per-task costs (1 worker process x 1 thread, TCP on loopback)\n")
    print("| scene | client: read + validate | payload through the scheduler | worker: "
          "payload to Scene (textures, BVH) | render, core-ns per sample | task overhead |")
    print("|---|---|---|---|---|---|")
    results = {}
    for name, path in scenes.items():
        c = costs(path, a.reps)
        results[name] = c
        print(f"| {name} | {c['client_s']:.2f} s | {c['sent'] / 1024:.1f} KiB | "
              f"{c['build_s']:.2f} s ({', '.join(f'{b:.2f}' for b in c['builds'])}) | "
              f"{c['per_sample'] * 1e9:.0f} ({c['render_cpu_s']:.2f} CPU s per image) | "
              f"{c['task_s'] * 1e3:.1f} ms |")
    print("\n## Predicted against measured (fresh local cluster of P worker processes x 1 "
          f"thread; wall of render_files, cluster start apart; median of {a.reps})\n")
    print("| scene | P | tasks | predicted s | measured s (runs) | cluster start s | "
          "predicted speed-up | measured speed-up |")
    print("|---|---|---|---|---|---|---|---|")
    for name, path in scenes.items():
        c = results[name]
        m = {P: measure(path, P, a.reps) for P in (1, 2)}
        pred = {P: predict(c, P, m[P]["tasks"])[0] for P in (1, 2)}
        for P in (1, 2):
            print(f"| {name} | {P} | {m[P]['tasks']} | {pred[P]:.2f} | {m[P]['wall']:.2f} "
                  f"({', '.join(f'{w:.2f}' for w in m[P]['walls'])}) | {m[P]['start']:.2f} | "
                  f"{pred[1] / pred[P]:.2f} | {m[1]['wall'] / m[P]['wall']:.2f} |")
    print("\nScaling (the model above, P one-core workers, these scenes' measured costs; "
          "~1 ms per task on a dedicated scheduler assumed beyond the measured overhead):\n")
    print("| scene | P | work / P s | serial s (client + build) | frame s | speed-up | "
          "efficiency |")
    print("|---|---|---|---|---|---|---|")
    for name, c in results.items():
        t1, work = predict(c, 1, 64)
        for P in (1, 2, 10, 100):
            tasks = max(64, 8 * P)
            tp, _ = predict(c, P, tasks)
            serial = c["client_s"] + c["build_s"]
            print(f"| {name} | {P} | {work / P:.2f} | {serial:.2f} | {tp:.2f} | "
                  f"{t1 / tp:.2f} | {t1 / tp / P * 100:.0f}% |")


if __name__ == "__main__":
    main()
