"""symbolic stage of symkin."""
