"""The PyQt5 window and its docks, built from a viewer session.  Never imports app.
"""
