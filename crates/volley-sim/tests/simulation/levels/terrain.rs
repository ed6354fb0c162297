//! Hard cases 20 and 23: a ball bouncing down a heightfield hill; a ball resting on a slope.
