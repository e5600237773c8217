"""The legged crawler: its model and robot file, its design, gait search and quasi-static walk.

- :mod:`~origami_cad.crawler.robot`: the robot file read and written (:class:`Robot`, its
  :class:`Leg`\\ s with their routes and servo IDs, point masses, blocker angle, friction,
  gait keyframes) and the parts it carries (``robot_placements``);
- :mod:`~origami_cad.crawler.design`: the parametric crawler (pattern, routes and robot
  file from design numbers, mm and degrees; the paper's 340 x 320 x 122 mm envelope), its
  robot file's comments in :mod:`~origami_cad.crawler.design_notes`;
- :mod:`~origami_cad.crawler.walk`: the robot walking quasi-statically on the ground
  (bar-and-hinge, stick-slip friction) and its gait as a servo sequence;
- :mod:`~origami_cad.crawler.gait`: CMA-ES gait search over frictions;
  :mod:`~origami_cad.crawler.design_search`: the joint design and gait search;
  :mod:`~origami_cad.crawler.gait_files`: what ``design-gait`` writes;
- :mod:`~origami_cad.crawler.mujoco`: the robot as a MuJoCo model, its gait played.

The package sits above ``simulation`` (it walks on its solver) and ``design`` (its
searches use the arm search's unit box); nothing below imports it.
"""
