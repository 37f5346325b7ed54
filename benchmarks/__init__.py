"""The lab on top of the product: benchmark drivers and experiments. They may import flows; nothing below imports
them, except `deformsmith bench l2`, whose command function loads `l2_schedule`.

`l2_schedule` (`deformsmith bench l2`), `l3_trial` (`python -m benchmarks.l3_trial`), `l3_yaw_sweep`
(`python -m benchmarks.l3_yaw_sweep`), `pick_and_place_video.py` (a script) and `engine/` (the MPM engine's GPU
benchmark scripts).
"""
