"""Time: a motion's and a marker set's clock, the sample grid and the one interpolator."""
