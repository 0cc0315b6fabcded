"""The rclpy side of ebm_wear_monitor (the only package that imports ROS).

``node`` (the ``wear_monitor`` node, a thin adapter over :mod:`ebm_wear_monitor.monitor`),
``parameters`` (declared ROS parameters, shipped config files), ``inputs`` (raw input buffers),
``messages`` (core results -> ``ebm_wear_msgs``), ``diagnostics`` (``/diagnostics``), ``qos``,
``player`` (publishes bags with their header stamps), ``listener`` (prints outputs as JSON lines).
"""
