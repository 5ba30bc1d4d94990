"""Entry point: `python3 scripts/lray_farm/__main__.py ARGS` (what scripts/farm runs)."""
import os
import sys

# Run as a file, not with -m: the package's parent (scripts/) goes on the path
# here, so that no PYTHONPATH leaks into lray or, through sbatch, into the jobs.
sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))

from lray_farm.cli import main  # noqa: E402

if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
