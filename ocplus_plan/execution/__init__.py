"""The executive: turns plans into joint actions, monitors the simulator and replans.

- :mod:`.paths`: BFS distances and multi-agent space-time path reservations.
- :mod:`.executive`: plan steps -> per-agent task queues, monitoring, replan triggers.
- :mod:`.faults`: fault injection (forced burns, extra switches, blockers, message loss).
"""
