"""Calibration from a video of the real object (issue #39): read the video, track the object, reduce the track to
L2's drop metrics, and fit E and the Kelvin-Voigt viscosity with the engine's own probes (the secant and bracketing
searches of tasks.export.calibrate); a flat-plate press test (CSV) is a second input to the same fit."""
