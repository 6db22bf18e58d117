"""Local feature size of a triangle mesh. The entry point is :mod:`.estimate`
(``estimate_lfs``, cached on the mesh object); it is split by concern into :mod:`.sites`,
:mod:`.features`, :mod:`.poles`, :mod:`.rounds` and :mod:`.result`, which rest on patches and
features, face sites, fitted midpoints, thickness, tangent balls and the Lipschitz envelope.
"""
