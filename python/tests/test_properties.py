"""Property-based tests of the Python layer (properties.py, with hypothesis): each property runs
in a child interpreter, so that a crash (abort, SIGSEGV) fails its test with the example it was
on, instead of ending pytest."""

import os
import subprocess
import sys
from pathlib import Path

import pytest

from conftest import plumetrace_with_core

pt = plumetrace_with_core()
import hypothesis  # noqa: E402,F401 -- Debian's python3-hypothesis (scripts/setup.sh); required

HERE = Path(__file__).resolve().parent
CHECKS = ["check_config_dicts_resolve_or_raise_naming_a_key",
          "check_runs_under_any_overrides_give_a_result_or_name_a_key",
          "check_sweeps_under_any_arguments_give_rows_or_name_the_argument",
          "check_runs_with_any_controller_give_a_result_or_its_error",
          "check_sweeps_with_any_controller_give_rows_or_its_error",
          "check_commands_take_finite_numbers_and_refuse_the_rest",
          "check_messages_take_four_finite_numbers_and_refuse_the_rest",
          "check_snapshots_convert_or_name_what_is_wrong",
          "check_env_episodes_under_any_actions_step_or_name_the_action",
          "check_params_of_any_fields_register_and_run_or_name_the_field",
          "check_register_controller_takes_any_names_params_and_classes_or_names_the_problem",
          "check_env_step_takes_a_heading_index_or_command_and_refuses_every_other_type",
          "check_summary_overhead_intervals_lie_within_the_successful_runs",
          "check_no_printed_or_drawn_overhead_bound_is_below_one"]


@pytest.mark.parametrize("check", CHECKS)
def test_property(check, tmp_path):
    # the package this pytest imported, and properties.py next to this file
    path = os.pathsep.join([str(HERE), str(Path(pt.__file__).resolve().parents[1])])
    # the timeout only stops a hang: a check takes seconds
    done = subprocess.run(
        [sys.executable, "-X", "faulthandler", "-c", f"import properties; properties.{check}()"],
        capture_output=True, text=True, timeout=600, cwd=tmp_path,
        env={**os.environ, "PYTHONPATH": path, "OPENBLAS_NUM_THREADS": "1"})
    lines = done.stdout.strip().splitlines()
    if done.returncode < 0:
        pytest.fail(f"the interpreter died of signal {-done.returncode} on the example\n"
                    f"{lines[-1] if lines else '(none)'}\n{done.stderr[-3000:]}")
    assert done.returncode == 0, f"{done.stdout[-3000:]}\n{done.stderr[-5000:]}"
