"""What the FloodWatch processes share: frames, message schemas, key expressions and the radio."""
