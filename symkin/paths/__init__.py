"""paths stage of symkin."""
