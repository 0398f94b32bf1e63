"""ORCA (van den Berg, Guy, Lin & Manocha, ISRR 2011): reciprocal collision avoidance in
continuous space, a safety layer any continuous controller can use, and shared guidance."""
