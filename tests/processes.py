"""Helpers for tests that run the command line as real processes."""

from __future__ import annotations

import os
import shlex
import shutil

import pytest


def unprivileged(cmd: list[str]) -> list[str]:
    """``cmd`` without the capabilities that let root ignore file permissions.

    As an ordinary user, ``cmd`` itself; as root, ``cmd`` under ``capsh`` with
    CAP_DAC_OVERRIDE, CAP_DAC_READ_SEARCH and CAP_FOWNER dropped (the test is skipped when
    capsh is missing).
    """
    if not hasattr(os, "geteuid") or os.geteuid() != 0:
        return cmd
    if shutil.which("capsh") is None:
        pytest.skip("running as root without capsh: permissions cannot be tested")
    drop = "--drop=cap_dac_override,cap_dac_read_search,cap_fowner"
    return ["capsh", drop, "--", "-c", "exec " + shlex.join(cmd)]
