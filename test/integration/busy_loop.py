#!/usr/bin/env python3
"""A busy loop for rostests that load the machine (one core's worth), until roslaunch stops it."""
while True:
    pass
