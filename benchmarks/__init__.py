"""The lab on top of the product: benchmark drivers, profiling and experiments. They may import flows; nothing in
contracts/, cache/, tasks/ or flows/ imports them (tests/layering/test_layers.py).

Each driver runs as `python -m benchmarks.<name>` (--help lists its options; --json prints its figures):
`mpm_bench` (the MPM step on the standard cube scene), `render_bench` (seconds per frame of the splat renderer),
`cache_bench` (cache put/hit and key latency, codec choice), `geometry_bench` (L0 per quality; --suite: a prompt
suite), `l2_schedule` (the L2 screening candidates under each schedule), `generate_rerun` (the main job rerun from a
full cache), `crosscheck_bench` (the asset in other simulators), `l3_trial`, `l3_yaw_sweep`, `blind_bench`,
`photo_bench`, `drop_video_bench`, `segmentation_sheet`, `calibrate_roundtrip` (`deformsmith calibrate` on rendered
drop videos of spheres with a known E and viscosity), `make_throughput_requests` (writes the default request set
of `deformsmith bench throughput`, throughput_requests.jsonl); `pick_and_place_video.py` (a script) and `engine/`
(the MPM engine's GPU benchmark scripts).
"""
