//! Hard cases 21 and 22: a grenade in a concave corner; a hit on a tick boundary.
