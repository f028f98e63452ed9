"""Run the simulator from a checkout: ``python simulator.py --help`` (the same program as the
installed ``robot-sim`` script; see robot_sim/app/main.py)."""
import sys

from robot_sim.app.main import Config, build_parser, config_from_args, launch, main

__all__ = ["Config", "build_parser", "config_from_args", "launch", "main"]

if __name__ == "__main__":
    sys.exit(main())
