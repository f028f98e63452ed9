"""The Qt-free viewer session: what a viewer shows (robot, desired pose, options), motion mode,
pick playback, recording, the workspace job.  Never imports qt or app.
"""
