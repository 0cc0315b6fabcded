"""Offline replay of rosbag2 recordings through the node's monitor core.

JSON of interface.md section 4, HTML report, prognostics metrics against ground truth.
"""
