"""Space: units, up axis, similarity transforms and fits, the figure's travel direction."""
