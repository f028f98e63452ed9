"""The ``robot-sim`` command line: parses and validates arguments, then calls the packages below.
"""
