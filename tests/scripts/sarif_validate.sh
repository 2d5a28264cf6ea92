#!/usr/bin/env bash
# SARIF output validated by Microsoft's SARIF multitool (see tests/sarif/validate.sh).
exec bash tests/sarif/validate.sh "$1"
