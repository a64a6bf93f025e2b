"""The `name: value` lines vocal's tools print (tum_odometry, bag_odometry, evaluate_trajectory), as a dict."""
import re


def metrics(text):
    values = {}
    for line in text.splitlines():
        match = re.match(r"^(\w+): ([-0-9.e+]+)$", line.strip())
        if match:
            values[match.group(1)] = float(match.group(2))
    return values
