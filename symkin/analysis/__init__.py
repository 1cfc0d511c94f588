"""analysis stage of symkin."""
