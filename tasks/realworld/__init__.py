"""The real-world validation (issue #39): the physics that turns a rule into our terms (Hertz squeeze, air drag), the
impact probe at a rule's drop speed and the comparison of our figures with the published ones."""
