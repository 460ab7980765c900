"""Test articles (rigid mass, MDOF, fluid-filled vessel) and sensors (report Sections 3.2, 7.2)."""
