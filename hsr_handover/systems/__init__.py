"""Drake plumbing both sides share: frame timing, required inputs, contact pairs and the check
of abstract connections."""
