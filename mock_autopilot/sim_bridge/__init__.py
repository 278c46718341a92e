"""The mock fleet's companion-computer side: camera frames and ground truth over Zenoh (see ``bridge.py``)."""
