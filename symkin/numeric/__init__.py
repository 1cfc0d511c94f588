"""numeric stage of symkin."""
