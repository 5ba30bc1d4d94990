"""scripts/farm: renders an LRay scene on a Slurm cluster as a job array.

scripts/farm is a thin wrapper around this package, so that the parts worth
testing (options, task lists, resume, the generated scripts, the summary) are
plain functions that tests/farm/test_farm_plan.py calls without lray or Slurm.
Standard library only: it runs on the submit host's python3.
"""
