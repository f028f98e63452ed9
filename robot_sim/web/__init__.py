"""The browser view of a viewer session (viser): a server bound to this machine unless told
otherwise (``server``), the scene sent as meshes once and poses after (``parts``,
``scene``), the interactive panel of ``robot-sim --web`` (``panel``, ``serve``), the
backend of ``rs.Visualizer(robot, backend="web")`` (``backend``) and the self-contained
HTML export (``export``).  Nothing here imports Qt or OpenGL, and no path that comes from
the browser is ever opened."""
